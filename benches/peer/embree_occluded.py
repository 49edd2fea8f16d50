"""Peer for shadow rays: Intel Embree 4 (through `embreex`, robust mode) answering occlusion (any-hit)
queries for a mesh on the pinhole camera rays of ../shared/peers/embree_render.py (the same formula),
with no distance limit. Prints the median time and the occluded rays:

    python3 embree_occluded.py --obj mesh.obj --eye 0,-4,0 --target 0,0,0 --fov 35 --size 400x400 \
        --threads 2 --reps 21 [--pin] [--warm-ms 250]

With `--pin` each worker thread runs on its own CPU (as the peer bench pins raylab's), so that the
scheduler cannot queue both on one. Before the clock starts, the workers cast the rays again and
again for `--warm-ms` milliseconds (at least once), as raylab's side does (see `warm_up`).
"""
import argparse
import itertools
import math
import os
import statistics
import threading
import time
from concurrent.futures import ThreadPoolExecutor

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh


def vec(s):
    return np.array([float(x) for x in s.split(',')])


def load_obj(path):
    vs, fs = [], []
    with open(path) as f:
        for line in f:
            parts = line.split()
            if not parts:
                continue
            if parts[0] == 'v':
                vs.append([float(x) for x in parts[1:4]])
            elif parts[0] == 'f':
                idx = [int(p.split('/')[0]) - 1 for p in parts[1:]]
                for k in range(1, len(idx) - 1):
                    fs.append([idx[0], idx[k], idx[k + 1]])
    return np.array(vs, float)[np.array(fs, np.int64)]


def thread_pool(threads, pin):
    """A pool of `threads` workers, started before any clock; with `pin`, worker k runs only on
    the k-th CPU this process may use."""
    cpus = sorted(os.sched_getaffinity(0))
    taken = itertools.count()

    def pin_this_thread():
        # sched_setaffinity(0, ...) sets the calling thread's CPUs on Linux.
        os.sched_setaffinity(0, {cpus[next(taken) % len(cpus)]})

    pool = ThreadPoolExecutor(threads, initializer=pin_this_thread if pin else None)
    # A pool starts a thread for each task that finds no idle one: tasks that wait for each other
    # start all `threads` of them here.
    barrier = threading.Barrier(threads)
    for f in [pool.submit(barrier.wait) for _ in range(threads)]:
        f.result()
    return pool


def warm_up(cast, ms):
    """Calls `cast` (the timed work, on the pool's workers) until `ms` milliseconds have passed, at
    least once. After the bench's other side has run, a worker that sat idle for a second took up
    to twice as long for its next casts (on a 2-vCPU machine, a cast of a few milliseconds read its
    one-thread time); a quarter of a second of work brings both back. Both sides warm up alike."""
    start = time.perf_counter()
    while True:
        cast()
        if (time.perf_counter() - start) * 1e3 >= ms:
            return


def pinhole(eye, target, fov, w, h):
    unit = lambda a: a / np.linalg.norm(a)
    fwd = unit(target - eye)
    right = unit(np.cross(fwd, [0.0, 0.0, 1.0]))
    up = np.cross(right, fwd)
    hh = math.tan(math.radians(fov) / 2.0)
    hw = hh * w / max(h, 1)
    u = (np.arange(w) + 0.5) / w * 2.0 - 1.0
    v = 1.0 - (np.arange(h) + 0.5) / h * 2.0
    U = np.tile(u, h)
    V = np.repeat(v, w)
    d = fwd[None, :] + (right[None, :] * U[:, None]) * hw + (up[None, :] * V[:, None]) * hh
    return np.broadcast_to(eye, d.shape).copy(), d


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--obj', required=True)
    ap.add_argument('--eye', type=vec, required=True)
    ap.add_argument('--target', type=vec, required=True)
    ap.add_argument('--fov', type=float, required=True)
    ap.add_argument('--size', required=True)
    ap.add_argument('--threads', type=int, default=2)
    ap.add_argument('--reps', type=int, default=21)
    ap.add_argument('--pin', action='store_true', help='each worker thread on its own CPU')
    ap.add_argument('--warm-ms', type=float, default=250.0,
                    help='milliseconds of casts on the workers before the clock starts')
    a = ap.parse_args()
    w, h = (int(x) for x in a.size.lower().split('x'))
    tris = np.ascontiguousarray(load_obj(a.obj), np.float32)
    scene = rtcs.EmbreeScene(robust=True)
    TriangleMesh(scene, tris)
    o, d = pinhole(a.eye, a.target, a.fov, w, h)
    o = np.ascontiguousarray(o, np.float32)
    d = np.ascontiguousarray(d, np.float32)
    rows = np.arange(w * h) // w
    parts = [(np.ascontiguousarray(o[rows % a.threads == k]), np.ascontiguousarray(d[rows % a.threads == k]))
             for k in range(a.threads)]
    pool = thread_pool(a.threads, a.pin)
    # embreex answers 0 for an occluded ray, -1 for a free one; this call also commits the scene.
    occluded = int((scene.run(o, d, query='OCCLUDED') == 0).sum())

    def cast():
        for f in [pool.submit(scene.run, po, pd, None, 'OCCLUDED') for po, pd in parts]:
            f.result()

    warm_up(cast, a.warm_ms)
    times = []
    for _ in range(a.reps):
        t0 = time.perf_counter()
        cast()
        times.append(time.perf_counter() - t0)
    ms = statistics.median(times) * 1e3
    print(f'median {ms:.3f} ms over {a.reps} queries of {w * h} rays ({a.threads} threads), '
          f'covered pixels {occluded} (occluded rays)')


if __name__ == '__main__':
    main()
