"""workflows/progress.py: the one progress mechanism (issue 12, item 6).

Truths: the rate and time left are arithmetic on the updates given (a fake
clock), the plain line parses back to the numbers it was made from, and a
terminal gets one redrawn line while a pipe gets rate-limited plain lines."""
import io

from dnarod.progress import Progress, duration, last_progress, md_rate, parse_line


class Clock:
    def __init__(self):
        self.t = 0.0

    def __call__(self):
        return self.t


class Tty(io.StringIO):
    def isatty(self):
        return True


def test_rate_and_time_left_in_a_pipe():
    clock, out = Clock(), io.StringIO()
    p = Progress("run-md", 100.0, "ps", stream=out, rate=md_rate, every_s=60.0, clock=clock)
    p.update(0.0)                 # the start: no line yet
    clock.t = 30.0
    p.update(5.0)                 # within 60 s of the start: no line
    clock.t = 100.0
    p.update(10.0)                # 10 ps in 100 s = 0.1 ps/s = 8.64 ns/day; 90 ps left = 900 s
    p.close()                     # a line was written, so the end gets one too
    lines = out.getvalue().splitlines()
    assert len(lines) == 2
    assert lines[0] == "run-md: progress 10/100 ps (10.0 %), 8.64 ns/day, 15:00 left"
    assert parse_line(lines[1])["done"] == "10"
    f = parse_line(lines[0])
    assert (f["label"], float(f["done"]), float(f["total"]), f["unit"], f["left"]) == \
        ("run-md", 10.0, 100.0, "ps", "15:00")


def test_a_short_step_is_quiet_in_a_pipe():
    """Shorter than every_s: nothing at all in a pipe (errors stay the first line)."""
    clock, out = Clock(), io.StringIO()
    p = Progress("run-md", 0.2, "ps", stream=out, every_s=60.0, clock=clock)
    for k in range(3):
        clock.t = 10.0 * k
        p.update(0.1 * k)
    p.close()
    assert out.getvalue() == ""


def test_terminal_redraws_one_line():
    clock, out = Clock(), Tty()
    p = Progress("x", 4, "steps", stream=out, clock=clock)
    for k in range(5):
        clock.t = k
        p.update(k)
    p.close()
    text = out.getvalue()
    assert text.count("\n") == 1 and text.count("\r") == 5
    assert text.rstrip().endswith("x: progress 4/4 steps (100.0 %), 1 steps/s, 0:00 left")


def test_last_progress_of_a_log_and_a_control(tmp_path):
    log = tmp_path / "run-md.log"
    log.write_text("noise\nrun-md: progress 1/600 ps (0.2 %)\nrun-md: progress 60/600 ps (10.0 %), "
                   "20 ns/day, 1:02:13 left\nmore noise\n")
    p = last_progress(log)
    assert float(p["done"]) == 60.0 and p["rate"] == "20 ns/day" and p["left"] == "1:02:13"
    assert last_progress(tmp_path / "missing.log") is None
    assert parse_line("step 100, will finish Tue Dec  1") is None
    assert duration(3733) == "1:02:13" and duration(59.6) == "1:00"
