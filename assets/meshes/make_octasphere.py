"""Writes octasphere.obj: an octahedron whose faces are split 8x8 and pushed onto the unit sphere.

The three great circles x = 0, y = 0 and z = 0 stay mesh edges with coordinates exactly 0, so a camera
on an axis sends whole pixel rows and columns exactly along shared edges: a crack test. Vertices are
shared by index, so the mesh is closed. Run: python3 make_octasphere.py > octasphere.obj
"""
import math

N = 8
vertices, index, faces = [], {}, []


def vertex(p):
    length = math.sqrt(sum(c * c for c in p))
    p = tuple(c / length + 0.0 for c in p)
    key = tuple(round(c, 9) for c in p)
    if key not in index:
        index[key] = len(vertices)
        vertices.append(p)
    return index[key]


for sx in (1, -1):
    for sy in (1, -1):
        for sz in (1, -1):
            a, b, c = (sx, 0, 0), (0, sy, 0), (0, 0, sz)
            if sx * sy * sz < 0:
                b, c = c, b
            grid = {}
            for i in range(N + 1):
                for j in range(N + 1 - i):
                    grid[i, j] = vertex([a[k] + i / N * (b[k] - a[k]) + j / N * (c[k] - a[k]) for k in range(3)])
            for i in range(N):
                for j in range(N - i):
                    faces.append((grid[i, j], grid[i + 1, j], grid[i, j + 1]))
                    if i + j < N - 1:
                        faces.append((grid[i + 1, j], grid[i + 1, j + 1], grid[i, j + 1]))

print("# octasphere: 8 octahedron faces split 8x8, on the unit sphere (make_octasphere.py)")
for x, y, z in vertices:
    print(f"v {x!r} {y!r} {z!r}")
for x, y, z in vertices:
    print(f"vn {x!r} {y!r} {z!r}")
for x, y, z in vertices:
    u = math.atan2(y, x) / (2 * math.pi) + 0.5
    v = math.asin(max(-1.0, min(1.0, z))) / math.pi + 0.5
    print(f"vt {u!r} {v!r}")
for f in faces:
    print("f " + " ".join(f"{i + 1}/{i + 1}/{i + 1}" for i in f))
