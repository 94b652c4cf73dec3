"""pim reconstruct's progress bar says the progress inside the Monte Carlo's stage (the fits
through the event report each chunk, pim.analysis.progress): a Monte Carlo of 10,000 samples
through the event (about a minute) moved the bar once, at its start."""

from pim.analysis.progress import report
from pim_cli import reconstruct as command
from pim_cli.main import main


def test_the_bar_shows_what_the_monte_carlo_reports(monkeypatch, capsys):
    real = command.run_reconstruction

    def reporting_run(*args, **kwargs):              # as the fits through the event do
        report(500, 1000, "samples fitted through the event")
        return real(*args, **kwargs)

    monkeypatch.setattr(command, "run_reconstruction", reporting_run)
    assert main(["reconstruct", "ricsac9-reconstruct", "--samples", "20", "--progress",
                 "--no-video"]) == 0
    err = capsys.readouterr().err
    assert "Monte Carlo: 500/1000 samples fitted through the event" in err, err
