"""Peer for each kind of ray raylab's tracer casts: Intel Embree 4 (through `embreex`, robust mode)
answering the same rays, written out by the peer bench, with the query the tracer asked: `intersect`
(the nearest hit: primary, sample, reflection and refraction rays) or `occluded` (any hit before
t_max: shadow and occlusion rays). Prints the median time and the rays that met something:

    python3 embree_rays.py --obj scene.obj --rays rays.f32 --query occluded --threads 2 --reps 5 [--pin] \
        [--warm-ms 250]

The rays file holds, per ray, seven little-endian f32s: origin x y z, direction x y z, t_max (+inf
for the nearest-hit kinds). The rays are split between the threads before the clock starts. With
`--pin` each worker thread runs on its own CPU, and for `--warm-ms` milliseconds before the clock
starts the workers cast the rays again and again, as in `embree_occluded.py`.

With `--serve` it loads the scene and the rays once, prints `ready, covered pixels N`, then answers
each line `WARM_MS REPS` on its standard input with a round: warm-up casts for WARM_MS
milliseconds, then the median of REPS timed casts (`median X ms`), until its input ends. The peer
bench alternates such rounds with raylab's, a moment apart, so that both sides of a round meet the
same moment of the machine (its busy spells slow the two sides unequally: see benches/README).
"""
import argparse
import statistics
import sys
import time

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

from embree_occluded import load_obj, thread_pool, warm_up


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--obj', required=True)
    ap.add_argument('--rays', required=True)
    ap.add_argument('--query', choices=['intersect', 'occluded'], required=True)
    ap.add_argument('--threads', type=int, default=2)
    ap.add_argument('--reps', type=int, default=5)
    ap.add_argument('--pin', action='store_true', help='each worker thread on its own CPU')
    ap.add_argument('--warm-ms', type=float, default=250.0,
                    help='milliseconds of casts on the workers before the clock starts')
    ap.add_argument('--serve', action='store_true',
                    help='answer rounds asked for on standard input ("WARM_MS REPS" a line)')
    a = ap.parse_args()
    tris = np.ascontiguousarray(load_obj(a.obj), np.float32)
    scene = rtcs.EmbreeScene(robust=True)
    TriangleMesh(scene, tris)
    rays = np.fromfile(a.rays, dtype='<f4').reshape(-1, 7)
    query = 'OCCLUDED' if a.query == 'occluded' else 'INTERSECT'
    # Embree's t_max is where the ray ends; the largest f32 stands in for +inf.
    far = np.minimum(rays[:, 6], np.finfo(np.float32).max)
    parts = [(np.ascontiguousarray(rays[k::a.threads, 0:3]),
              np.ascontiguousarray(rays[k::a.threads, 3:6]),
              np.ascontiguousarray(far[k::a.threads]))
             for k in range(a.threads)]

    def met(o, d, t):
        # embreex answers 0 for an occluded ray and -1 for a free one; a primitive index or -1
        # for an intersection.
        answer = scene.run(o, d, t, query)
        return int((answer == 0).sum()) if query == 'OCCLUDED' else int((answer >= 0).sum())

    pool = thread_pool(a.threads, a.pin)
    # The first call also commits the scene.
    hits = sum(met(*p) for p in parts)

    def cast():
        for f in [pool.submit(met, *p) for p in parts]:
            f.result()

    def round_ms(warm_ms, reps):
        warm_up(cast, warm_ms)
        times = []
        for _ in range(reps):
            t0 = time.perf_counter()
            cast()
            times.append(time.perf_counter() - t0)
        return statistics.median(times) * 1e3

    if a.serve:
        print(f'ready, covered pixels {hits}', flush=True)
        for line in sys.stdin:
            warm_ms, reps = line.split()
            print(f'median {round_ms(float(warm_ms), max(1, int(reps))):.3f} ms', flush=True)
        return
    ms = round_ms(a.warm_ms, a.reps)
    print(f'median {ms:.3f} ms over {a.reps} queries of {len(rays)} rays ({a.threads} threads), '
          f'covered pixels {hits} (rays that met something)')


main()
