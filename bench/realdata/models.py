#!/usr/bin/env python3
"""COLMAP text models for the hold-out benchmark (no dependencies beyond Python 3).

  models.py strecha CAMERAS_DIR OUT_DIR     true cameras of a Strecha et al. set (one
                                            <image>.camera file per image) as a PINHOLE model
  models.py subset MODEL_TXT_DIR OUT_DIR NAME...
                                            the named images of a text model, with their cameras
  models.py without MODEL_TXT_DIR OUT_DIR NAME
                                            the model without one image: its observations leave
                                            the tracks, points seen by fewer than 2 images go
"""
import math
import os
import sys


def quaternion(r):
    """(w, x, y, z) of a rotation matrix given as 3 rows (Shepperd's method)."""
    trace = r[0][0] + r[1][1] + r[2][2]
    if trace > 0:
        s = 0.5 / math.sqrt(trace + 1.0)
        return (0.25 / s, (r[2][1] - r[1][2]) * s, (r[0][2] - r[2][0]) * s, (r[1][0] - r[0][1]) * s)
    i = max(range(3), key=lambda k: r[k][k])
    j, k = (i + 1) % 3, (i + 2) % 3
    s = 2.0 * math.sqrt(1.0 + r[i][i] - r[j][j] - r[k][k])
    q = [0.0] * 4
    q[0] = (r[k][j] - r[j][k]) / s
    q[1 + i] = 0.25 * s
    q[1 + j] = (r[j][i] + r[i][j]) / s
    q[1 + k] = (r[k][i] + r[i][k]) / s
    return tuple(q)


def read_strecha(path):
    """K, camera-to-world R, centre C and size of one .camera file."""
    rows = [line.split() for line in open(path) if line.strip()]
    if len(rows) < 9:
        sys.exit(f"{path}: expected 9 lines (K, distortion, R, C, size), found {len(rows)}")
    numbers = [[float(v) for v in row] for row in rows[:9]]
    return numbers[0:3], numbers[4:7], numbers[7], [int(float(v)) for v in numbers[8][:2]]


def write_model(out, cameras, images):
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "cameras.txt"), "w") as f:
        for cam_id, line in cameras:
            f.write(f"{cam_id} {line}\n")
    with open(os.path.join(out, "images.txt"), "w") as f:
        for line in images:
            f.write(line + "\n\n")
    open(os.path.join(out, "points3D.txt"), "w").close()


def strecha(cameras_dir, out):
    cameras, images = [], []
    files = sorted(n for n in os.listdir(cameras_dir) if n.endswith(".camera"))
    if not files:
        sys.exit(f"{cameras_dir}: no .camera files")
    for index, name in enumerate(files, start=1):
        k, r_world, c, (w, h) = read_strecha(os.path.join(cameras_dir, name))
        # x ~ K R^T (X - C): cam_from_world rotation R^T, translation -R^T C.
        r = [[r_world[j][i] for j in range(3)] for i in range(3)]
        t = [-sum(r[i][j] * c[j] for j in range(3)) for i in range(3)]
        q = quaternion(r)
        cameras.append((index, f"PINHOLE {w} {h} {k[0][0]!r} {k[1][1]!r} {k[0][2]!r} {k[1][2]!r}"))
        values = " ".join(repr(v) for v in (*q, *t))
        images.append(f"{index} {values} {index} {name[:-len('.camera')]}")
    write_model(out, cameras, images)


def subset(model, out, names):
    lines = [l.rstrip("\n") for l in open(os.path.join(model, "images.txt")) if not l.startswith("#")]
    images, wanted_cameras = [], set()
    for i in range(0, len(lines) - 1, 2):
        fields = lines[i].split()
        if len(fields) >= 10 and fields[9] in names:
            images.append(lines[i])
            wanted_cameras.add(fields[8])
    missing = set(names) - {l.split()[9] for l in images}
    if missing:
        sys.exit(f"{model}: no image named {', '.join(sorted(missing))}")
    cameras = []
    for line in open(os.path.join(model, "cameras.txt")):
        fields = line.split(maxsplit=1)
        if fields and not line.startswith("#") and fields[0] in wanted_cameras:
            cameras.append((fields[0], fields[1].strip()))
    write_model(out, cameras, images)


def without(model, out, name):
    lines = [l.rstrip("\n") for l in open(os.path.join(model, "images.txt")) if not l.startswith("#")]
    images, dropped = [], None
    for i in range(0, len(lines) - 1, 2):
        fields = lines[i].split()
        if len(fields) >= 10 and fields[9] == name:
            dropped = fields[0]
        elif len(fields) >= 10:
            images.append(lines[i] + "\n" + lines[i + 1])
    if dropped is None:
        sys.exit(f"{model}: no image named {name}")
    os.makedirs(out, exist_ok=True)
    with open(os.path.join(out, "images.txt"), "w") as f:
        f.write("\n".join(images) + "\n")
    with open(os.path.join(model, "cameras.txt")) as src, open(os.path.join(out, "cameras.txt"), "w") as f:
        f.write(src.read())
    with open(os.path.join(model, "points3D.txt")) as src, open(os.path.join(out, "points3D.txt"), "w") as f:
        for line in src:
            fields = line.split()
            if not fields or line.startswith("#"):
                continue
            track = [(fields[k], fields[k + 1]) for k in range(8, len(fields) - 1, 2) if fields[k] != dropped]
            if len({image for image, _ in track}) >= 2:
                f.write(" ".join(fields[:8] + [v for pair in track for v in pair]) + "\n")


if __name__ == "__main__":
    if len(sys.argv) >= 4 and sys.argv[1] == "strecha":
        strecha(sys.argv[2], sys.argv[3])
    elif len(sys.argv) == 5 and sys.argv[1] == "without":
        without(sys.argv[2], sys.argv[3], sys.argv[4])
    elif len(sys.argv) >= 5 and sys.argv[1] == "subset":
        subset(sys.argv[2], sys.argv[3], sys.argv[4:])
    else:
        sys.exit(__doc__)
