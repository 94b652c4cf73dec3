"""Off-screen animations: the simulated motion solid with PIM's motion as a ghost."""
