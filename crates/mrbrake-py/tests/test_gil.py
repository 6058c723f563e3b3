"""Long solves release the GIL: two analyses on two threads run at the same time.

Each analysis reports the wall-clock time it spent inside the library (`timings_s.total`); its
end is taken on the calling thread right after it returns. The intervals [end - total, end] of the
two threads must overlap, which they cannot if one thread held the GIL through its whole solve."""

import time
from concurrent.futures import ThreadPoolExecutor

import mrbrake


def timed_analysis(_):
    a = mrbrake.analyze(mesh="coarse", currents=4)
    end = time.perf_counter()
    return end - a.timings_s["total"], end


def test_two_threads_analyse_at_the_same_time():
    with ThreadPoolExecutor(max_workers=2) as pool:
        (s1, e1), (s2, e2) = pool.map(timed_analysis, range(2))
    overlap = min(e1, e2) - max(s1, s2)
    assert overlap > 0.0, f"library intervals [{s1:.3f}, {e1:.3f}] and [{s2:.3f}, {e2:.3f}]"


def test_python_runs_while_an_analysis_solves():
    """The main thread keeps running Python code during a solve on another thread."""
    with ThreadPoolExecutor(max_workers=1) as pool:
        future = pool.submit(timed_analysis, 0)
        ticks = []
        while not future.done():
            ticks.append(time.perf_counter())
            time.sleep(0.001)
        start, end = future.result()
    inside = [t for t in ticks if start < t < end]
    assert len(inside) >= 10, f"{len(inside)} main-thread ticks in {end - start:.3f} s of solve"
