"""relief releases the GIL while it traces: other Python threads run meanwhile, and calls
from several threads at once give the results of one call alone."""

import threading
import time

import numpy as np

import relief
from conftest import hills


def test_other_threads_run_while_relief_traces():
    heights = hills(512, 512)
    rng = np.random.default_rng(1)
    n = 1_000_000
    origins = np.column_stack([rng.uniform(0, 512, n), rng.uniform(0, 512, n), np.full(n, 20.0)])
    directions = np.column_stack([rng.uniform(-1, 1, n), rng.uniform(-1, 1, n), np.full(n, -0.01)])
    took = []

    def trace():
        # Three calls: each long enough that the GIL held for one of them would show as a gap
        # of the main thread's ticks far longer than scheduling noise.
        for _ in range(3):
            start = time.perf_counter()
            relief.intersect(heights, origins, directions, tracer="naive")
            took.append(time.perf_counter() - start)

    worker = threading.Thread(target=trace)
    ticks = []
    worker.start()
    while worker.is_alive():
        ticks.append(time.perf_counter())
        time.sleep(0.001)
    worker.join()
    gaps = np.diff(ticks)
    shortest = min(took)
    assert shortest > 0.05, took
    # With the GIL held for a whole call this thread would stall for all of it.
    assert len(gaps) > 30 and gaps.max() < 0.5 * shortest, (gaps.max(), took)

def test_concurrent_calls_give_the_results_of_one_call():
    heights = hills()
    alone = relief.render(heights, size=(48, 32))
    results = [None] * 4

    def run(k):
        results[k] = relief.render(heights, size=(48, 32))

    threads = [threading.Thread(target=run, args=(k,)) for k in range(4)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    for rgb, depth in results:
        assert np.array_equal(rgb, alone[0]) and np.array_equal(depth, alone[1])


def test_shade_on_any_number_of_threads_gives_the_same_bits():
    heights = hills(96, 80)
    layers = ["shadow", "sky", "horizon"]
    shared = relief.shade(heights, 2.0, layers=layers, azimuths=8)
    for threads in (1, 3):
        own = relief.shade(heights, 2.0, layers=layers, azimuths=8, threads=threads)
        for name in layers:
            assert own[name].tobytes() == shared[name].tobytes(), (threads, name)


def test_no_thread_is_refused():
    try:
        relief.shade(hills(16, 16), 1.0, threads=0)
    except relief.ReliefError as error:
        assert "threads must be at least 1" in str(error)
    else:
        raise AssertionError("threads=0 was accepted")


def test_a_scene_renders_the_same_picture_on_any_number_of_threads(tmp_path):
    np.save(tmp_path / "h.npy", hills(64, 72).astype(np.float32))
    scene = relief.open(tmp_path / "h.npy", spacing=2.0, shadows=True)
    rgb, depth = scene.render(size=(96, 64))
    for threads in (1, 3):
        own_rgb, own_depth = scene.render(size=(96, 64), threads=threads)
        assert np.array_equal(own_rgb, rgb), threads
        assert own_depth.tobytes() == depth.tobytes(), threads
    try:
        scene.render(size=(96, 64), threads=0)
    except relief.ReliefError as error:
        assert "threads must be at least 1" in str(error)
    else:
        raise AssertionError("threads=0 was accepted")
