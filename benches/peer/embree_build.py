"""Peer for building the hierarchy: Intel Embree 4 (through `embreex`, robust mode) builds its BVH
over a mesh, and says how long the build took and how much memory it took (the growth of the
process's resident memory across the build, read from /proc/self/statm). Prints one line:

    python3 embree_build.py --obj mesh.obj --reps 3
    -> median build 812.4 ms over 3 builds, BVH 95.1 MiB, mesh buffers 15.0 MiB, triangles 1310720

The memory is the first build's, in a fresh process (a later one may reuse pages freed before it).
Each build is a new scene (the mesh copied in, then the first query commits it, which builds).
Embree uses every hardware thread for the build.
"""
import argparse
import gc
import os
import statistics
import time

import numpy as np
from embreex import rtcore_scene as rtcs
from embreex.mesh_construction import TriangleMesh

from embree_occluded import load_obj

PAGE = os.sysconf('SC_PAGE_SIZE')


def resident():
    with open('/proc/self/statm') as f:
        return int(f.read().split()[1]) * PAGE


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument('--obj', required=True)
    ap.add_argument('--reps', type=int, default=3)
    a = ap.parse_args()
    tris = np.ascontiguousarray(load_obj(a.obj), np.float32)
    o = np.zeros((1, 3), np.float32)
    d = np.ones((1, 3), np.float32)
    times, bvh, buffers = [], [], []
    for _ in range(a.reps):
        gc.collect()
        before = resident()
        scene = rtcs.EmbreeScene(robust=True)
        TriangleMesh(scene, tris)
        meshed = resident()
        t0 = time.perf_counter()
        scene.run(o, d)
        times.append(time.perf_counter() - t0)
        bvh.append(resident() - meshed)
        buffers.append(meshed - before)
        del scene
    mib = 1024 * 1024
    # The memory of the first build, in a fresh process (a later one may reuse freed pages).
    print(f'median build {statistics.median(times) * 1e3:.1f} ms over {a.reps} builds, '
          f'BVH {bvh[0] / mib:.1f} MiB, mesh buffers {buffers[0] / mib:.1f} MiB, '
          f'triangles {len(tris)}')


main()
