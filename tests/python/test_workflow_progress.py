"""workflows/progress.py: the one progress mechanism.

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


def test_terminal_redraws_at_most_every_tenth_of_a_second_and_ends_on_the_last_state():
    clock, out = Clock(), Tty()
    p = Progress("x", 100, "steps", stream=out, clock=clock)
    for k in range(101):          # 100 updates within 0.1 s: one drawn, the rest pending
        clock.t = k * 0.0009
        p.update(k)
    p.close()
    text = out.getvalue()
    assert text.count("\r") == 2, text       # the first update and, at close, the last state
    assert text.rstrip().endswith("x: progress 100/100 steps (100.0 %), 1.11e+03 steps/s, 0:00 left")


def test_other_output_goes_above_the_live_line():
    clock, out = Clock(), Tty()
    p = Progress("x", 4, "jobs", stream=out, clock=clock)
    p.above("before any line")
    p.update(1)
    p.above("rule md_run:")
    p.close()
    assert out.getvalue() == ("before any line\n\r\033[Kx: progress 1/4 jobs (25.0 %)"
                              "\r\033[Krule md_run:\nx: progress 1/4 jobs (25.0 %)\n")
    pipe = io.StringIO()
    q = Progress("x", 4, "jobs", stream=pipe, clock=clock)
    q.update(1)
    q.above("rule md_run:")
    q.close()
    assert pipe.getvalue() == "rule md_run:\n"


def test_stages_close_the_previous_stage_and_end_the_line_before_a_warning():
    import warnings
    from dnarod.progress import Stages
    clock, out = Clock(), Tty()
    saved = warnings.showwarning
    # what warnings.warn calls to print a warning, here writing where the progress goes
    warnings.showwarning = lambda message, *args, **kw: out.write(f"warning: {message}\n")
    try:
        with Stages("build-md", stream=out, clock=clock) as stages:
            stages("minimisation", 10, 5000, "steps")
            warnings.showwarning("em did not converge", UserWarning, "inputs.py", 1)
            clock.t = 1.0
            stages("equilibration", 0.1, 0.2, "ps")
    finally:
        warnings.showwarning = saved
    text = out.getvalue()
    # the minimisation line ends before the warning; the equilibration line is ended at exit
    assert "build-md: minimisation: progress 10/5000 steps (0.2 %)\nwarning: em did not converge\n" in text
    assert text.endswith("build-md: equilibration: progress 0.1/0.2 ps (50.0 %)\n")


def test_no_time_left_for_a_stage_with_a_step_limit():
    """A minimisation's total is a limit it rarely reaches (it stops when converged):
    its line gives the rate but no time left, and still parses."""
    import io
    now = [0.0]
    s = io.StringIO()
    p = Progress("build-md: minimisation", 5000, "steps", stream=s, every_s=5.0, clock=lambda: now[0],
                 time_left=False)
    p.update(1)
    now[0] = 10.0
    p.update(51)
    text = s.getvalue().splitlines()[-1]
    assert text == "build-md: minimisation: progress 51/5000 steps (1.0 %), 5 steps/s"
    f = parse_line(text)
    assert f is not None and f["left"] is None and float(f["done"]) == 51
