"""The progress line of `floorscan run` (tqdm): shown on a terminal only, counting frames and
skips."""

import io

from floorscan.pipeline.progress import Progress


class Terminal(io.StringIO):
    def isatty(self):
        if self.closed:  # as real streams do
            raise ValueError("I/O operation on closed file")
        return True


def test_progress_counts_frames_and_skips_on_a_terminal():
    out = Terminal()
    p = Progress(10, stream=out)
    for done in range(1, 8):
        p.update(done, skipped=2 if done > 5 else 0)
    p.close()
    text = out.getvalue()
    assert "7/10" in text
    assert "skipped=2" in text


def test_no_progress_line_when_not_a_terminal():
    out = io.StringIO()
    p = Progress(10, stream=out)
    p.update(5)
    p.close()
    assert out.getvalue() == ""


def test_a_closed_stream_disables_the_line():
    out = Terminal()
    out.close()
    p = Progress(None, stream=out)
    assert p.bar.disable
    p.update(1)
    p.close()
