"""Studies of the model and the simulator: PIM's assumptions (the ladder), the tuned crush
scene against published crash tests, pulses, speed against error, the hard cases, the
stiff limit, energy gain, runs under other impact laws, the coefficients a comparison uses."""
