#!/usr/bin/env python3
"""Cross-check `trackd vfh` against PCL's VFHEstimation (and NormalEstimation) on a real scan.

1. The points of a KITTI tracking scan above the road (z > -1.4 m, range 0.5-50 m) are
   clustered with `trackd cluster` (default parameters) and described with
   `trackd vfh --normals-out` (k = 10 normals, viewpoint = sensor origin).
2. `pcl_vfh` (tests/python/pcl_vfh.cpp, linked against PCL 1.13) computes, per cluster,
   PCL's VFHSignature308 (a) from trackd's normals and (b) from PCL's own NormalEstimation
   (k = 10, same viewpoint), and returns PCL's normals.
3. Reported: (a) how many clusters' histograms are identical to PCL's, and the largest bin
   difference (the histogram stage alone); (b) the angle between trackd's and PCL's normals
   and the chi-squared distance between trackd's and PCL's end-to-end histograms.

Fails (exit 1) when (a) differs by more than 1e-3 in any bin of more than 1 % of the clusters.

Usage: python3 tests/python/check_vfh_pcl.py [--trackd PATH] [--pcl-vfh PATH] [--data DIR]
`--pcl-vfh` defaults to building tests/python/pcl_vfh.cpp with g++; include folders come from
$PCL_INCLUDE (default /usr/include/pcl-1.13), $FLANN_INCLUDE and $EIGEN_INCLUDE
(default /usr/include/eigen3); on Debian: apt-get install libpcl-dev.
"""

import argparse
import os
import shutil
import struct
import subprocess
import sys
import tempfile

import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
BINS = 308


def find_trackd(given):
    if given:
        return given
    root = os.path.dirname(os.path.dirname(HERE))
    for candidate in (os.path.join(root, "target", "release", "trackd"), shutil.which("trackd")):
        if candidate and os.path.exists(candidate):
            return candidate
    sys.exit("trackd binary not found: build it (cargo build --release -p trackd) or pass --trackd")


def build_pcl_vfh(workdir):
    include = os.environ.get("PCL_INCLUDE", "/usr/include/pcl-1.13")
    eigen = os.environ.get("EIGEN_INCLUDE", "/usr/include/eigen3")
    flann = os.environ.get("FLANN_INCLUDE")
    libdir = os.environ.get("PCL_LIBDIR", "/usr/lib/x86_64-linux-gnu")
    libs = []
    for name in ("features", "search", "kdtree", "common"):
        plain = os.path.join(libdir, f"libpcl_{name}.so")
        versioned = sorted(p for p in os.listdir(libdir) if p.startswith(f"libpcl_{name}.so."))
        libs.append(plain if os.path.exists(plain) else os.path.join(libdir, versioned[0]))
    binary = os.path.join(workdir, "pcl_vfh")
    cmd = ["g++", "-O2", "-std=c++17", "-I" + include, "-I" + eigen]
    if flann:
        cmd.append("-I" + flann)
    cmd += [os.path.join(HERE, "pcl_vfh.cpp"), "-o", binary] + libs
    subprocess.run(cmd, check=True)
    return binary


def above_road(xyz):
    r = np.linalg.norm(xyz, axis=1)
    return xyz[(r >= 0.5) & (r <= 50.0) & (xyz[:, 2] > -1.4)]


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trackd")
    parser.add_argument("--pcl-vfh", help="a built tests/python/pcl_vfh.cpp")
    parser.add_argument("--data", default=None)
    parser.add_argument("--frame", default="000000")
    args = parser.parse_args()
    trackd = find_trackd(args.trackd)
    data = args.data or os.path.normpath(os.path.join(HERE, "..", "..", "..", "shared", "data"))
    if not os.path.isdir(data):
        data = "/work/shared/data"
    scan = os.path.join(data, "kitti-tracking-0000-first40", "training", "velodyne", "0000", args.frame + ".bin")
    if not os.path.exists(scan):
        sys.exit(f"{scan} not found: cannot cross-check on real scans")

    with tempfile.TemporaryDirectory() as work:
        pcl_vfh = args.pcl_vfh or build_pcl_vfh(work)
        xyz = above_road(np.fromfile(scan, dtype="<f4").reshape(-1, 4)[:, :3]).astype("<f4")
        points = os.path.join(work, "points.xyz")
        xyz.tofile(points)
        labels = os.path.join(work, "labels.i32")
        csv = os.path.join(work, "vfh.csv")
        normals_path = os.path.join(work, "normals.f32")
        subprocess.run([trackd, "cluster", points, "--out", labels], check=True, stderr=subprocess.DEVNULL)
        subprocess.run(
            [trackd, "vfh", points, labels, "--max-points", "0", "--out", csv, "--normals-out", normals_path],
            check=True,
            stderr=subprocess.DEVNULL,
        )
        label = np.fromfile(labels, dtype="<i4")
        normals = np.fromfile(normals_path, dtype="<f4").reshape(-1, 3)
        rows = np.loadtxt(csv, delimiter=",", skiprows=1, ndmin=2)
        clusters = rows[:, 0].astype(int)
        ours = rows[:, 2:].astype(np.float32)

        request = os.path.join(work, "clusters.bin")
        members = []
        with open(request, "wb") as f:
            f.write(struct.pack("<II", len(clusters), 10))
            for c in clusters:
                idx = np.flatnonzero(label == c)
                members.append(idx)
                f.write(struct.pack("<I3f", len(idx), 0.0, 0.0, 0.0))
                f.write(np.hstack([xyz[idx], normals[idx]]).astype("<f4").tobytes())
        answer = os.path.join(work, "pcl.bin")
        subprocess.run([pcl_vfh, request, answer], check=True)
        raw = np.fromfile(answer, dtype="<f4")

    offset = 0
    identical = 0
    worst = 0.0
    bad = 0
    angles = []
    chi2 = []
    for k, idx in enumerate(members):
        given = raw[offset:offset + BINS]
        own = raw[offset + BINS:offset + 2 * BINS]
        pcl_normals = raw[offset + 2 * BINS:offset + 2 * BINS + 3 * len(idx)].reshape(-1, 3)
        offset += 2 * BINS + 3 * len(idx)
        diff = np.abs(given - ours[k]).max()
        worst = max(worst, float(diff))
        identical += int(np.array_equal(given, ours[k]))
        bad += int(diff > 1e-3)
        cos = np.clip(np.sum(pcl_normals * normals[idx], axis=1), -1.0, 1.0)
        angles.append(np.degrees(np.arccos(cos)))
        p, q = own / own.sum(), ours[k] / ours[k].sum()
        s = p + q
        chi2.append(0.5 * float(np.sum(np.where(s > 0, (p - q) ** 2 / np.where(s > 0, s, 1), 0))))
    angles = np.concatenate(angles)
    chi2 = np.array(chi2)
    n = len(members)
    print(f"scan {os.path.basename(scan)}: {len(xyz)} points above the road, {n} clusters described")
    print(f"(a) PCL VFHEstimation on trackd's normals: {identical}/{n} clusters bit-identical, "
          f"{bad} with a bin off by > 1e-3, largest bin difference {worst:.6g}")
    print(f"(b) PCL NormalEstimation vs trackd normals: median angle {np.median(angles):.4f} deg, "
          f"95th pct {np.percentile(angles, 95):.4f} deg, {100 * np.mean(angles < 1.0):.2f} % under 1 deg, "
          f"{100 * np.mean(angles > 90.0):.2f} % flipped")
    print(f"    end-to-end histograms (PCL normals + PCL VFH vs trackd): chi2 median {np.median(chi2):.5f}, "
          f"95th pct {np.percentile(chi2, 95):.5f}, max {chi2.max():.5f}")
    ok = bad <= 0.01 * n
    print("OK" if ok else "MISMATCH")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
