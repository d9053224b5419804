"""The progress bar of long loops: silent when asked or when stderr is not a terminal."""

from stability.util.progress import progress_bar


def test_a_silent_bar_accepts_every_call(capsys):
    for progress in (False, None):  # under pytest stderr is not a terminal
        bar = progress_bar(3, progress, "test", unit="run")
        bar.set_postfix_str("first")
        bar.update(1)
        bar.close()
    assert capsys.readouterr().err == ""


def test_a_requested_bar_counts(capsys):
    bar = progress_bar(2, True, "test", unit="run")
    bar.update(2)
    assert bar.n == 2
    bar.close()
