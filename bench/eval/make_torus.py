"""Writes a closed torus (major radius 2) as a binary PLY: nu x nv grid, 2*nu*nv faces."""
import math
import struct
import sys

path, nu, nv, minor = sys.argv[1], int(sys.argv[2]), int(sys.argv[3]), float(sys.argv[4])
with open(path, "wb") as f:
    f.write(("ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\n"
             "property float z\nelement face %d\nproperty list uchar int vertex_indices\nend_header\n"
             % (nu * nv, 2 * nu * nv)).encode())
    for i in range(nu):
        u = 2 * math.pi * i / nu
        cu, su = math.cos(u), math.sin(u)
        f.write(b"".join(struct.pack("<3f", (2 + minor * math.cos(2 * math.pi * j / nv)) * cu,
                                     (2 + minor * math.cos(2 * math.pi * j / nv)) * su,
                                     minor * math.sin(2 * math.pi * j / nv)) for j in range(nv)))
    for i in range(nu):
        i1 = (i + 1) % nu
        rows = []
        for j in range(nv):
            j1 = (j + 1) % nv
            a, b, c, d = i * nv + j, i1 * nv + j, i1 * nv + j1, i * nv + j1
            rows.append(struct.pack("<B3iB3i", 3, a, b, c, 3, a, c, d))
        f.write(b"".join(rows))
