#!/usr/bin/env python3
"""Cross-check `trackd cluster` against scikit-learn's DBSCAN on real KITTI scans.

For each scan and (eps, min_points) pair, runs

    trackd cluster POINTS --eps E --min-points M --out labels.i32 --core-out core.u8

and `sklearn.cluster.DBSCAN(eps=E, min_samples=M, algorithm='kd_tree')` on the same float32
points (scikit-learn widens them to float64), then requires identical labels (same cluster
numbers, so adjusted Rand index 1.0) and identical core points. Both neighbour indexes of
trackd (grid and k-d tree) are checked.

Scans: a full KITTI odometry `.bin` (every point, ground included), a KITTI raw `.pcd`, and
`.xyz` files this script writes with the points of a tracking scan above the road (z > -1.4 m,
range 0.5-50 m), i.e. roughly what DBSCAN sees in the pipeline.

Usage: python3 tests/python/check_dbscan.py [--trackd PATH] [--data DIR]
Needs: numpy, scikit-learn. Exit status 0 when everything matches, 1 otherwise.
"""

import argparse
import os
import shutil
import subprocess
import sys
import tempfile
import time

import numpy as np
from sklearn.cluster import DBSCAN
from sklearn.metrics import adjusted_rand_score


def find_trackd(given):
    if given:
        return given
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.path.dirname(os.path.dirname(here))
    for candidate in (
        os.path.join(root, "target", "release", "trackd"),
        shutil.which("trackd"),
    ):
        if candidate and os.path.exists(candidate):
            return candidate
    sys.exit("trackd binary not found: build it (cargo build --release -p trackd) or pass --trackd")


def read_bin(path):
    return np.fromfile(path, dtype="<f4").reshape(-1, 4)[:, :3]


def read_pcd(path):
    """Binary PCD with FIELDS x y z intensity (KITTI raw here): header, then POINTS x 16 bytes."""
    with open(path, "rb") as f:
        data = f.read()
    points = None
    offset = 0
    for line in data.split(b"\n"):
        offset += len(line) + 1
        if line.startswith(b"POINTS"):
            points = int(line.split()[1])
        if line.startswith(b"DATA"):
            if line.split()[1] != b"binary":
                sys.exit(f"{path}: only binary PCD is read here")
            break
    cloud = np.frombuffer(data, dtype="<f4", count=points * 4, offset=offset)
    return cloud.reshape(-1, 4)[:, :3]


def above_road(xyz):
    r = np.linalg.norm(xyz, axis=1)
    return xyz[(r >= 0.5) & (r <= 50.0) & (xyz[:, 2] > -1.4)]


def run_trackd(trackd, path, eps, min_points, index, workdir):
    labels_path = os.path.join(workdir, "labels.i32")
    core_path = os.path.join(workdir, "core.u8")
    cmd = [
        trackd, "cluster", path,
        "--eps", repr(eps), "--min-points", str(min_points), "--index", index,
        "--out", labels_path, "--core-out", core_path,
    ]
    subprocess.run(cmd, check=True, stderr=subprocess.DEVNULL)
    labels = np.fromfile(labels_path, dtype="<i4")
    core = np.fromfile(core_path, dtype=np.uint8).astype(bool)
    return labels, core


def check(trackd, name, path, xyz, eps, min_points, workdir):
    start = time.time()
    model = DBSCAN(eps=eps, min_samples=min_points, algorithm="kd_tree").fit(xyz.astype(np.float64))
    sk_seconds = time.time() - start
    sk_core = np.zeros(len(xyz), dtype=bool)
    sk_core[model.core_sample_indices_] = True
    ok = True
    for index in ("grid", "kd-tree"):
        labels, core = run_trackd(trackd, path, eps, min_points, index, workdir)
        same_labels = labels.shape == model.labels_.shape and np.array_equal(labels, model.labels_)
        ari = adjusted_rand_score(model.labels_, labels) if labels.shape == model.labels_.shape else float("nan")
        same_core = core.shape == sk_core.shape and np.array_equal(core, sk_core)
        status = "OK" if same_labels and same_core else "MISMATCH"
        ok &= status == "OK"
        clusters = int(model.labels_.max()) + 1
        print(
            f"{status:8} {name:38} n={len(xyz):6} eps={eps:<4} min_points={min_points:<2} "
            f"index={index:7} clusters={clusters:4} noise={int((model.labels_ < 0).sum()):5} "
            f"core={int(sk_core.sum()):6} ARI={ari:.6f} labels_identical={same_labels} "
            f"core_identical={same_core} (sklearn {sk_seconds:.1f} s)"
        )
    return ok


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--trackd", help="path to the trackd binary (default: target/release/trackd)")
    parser.add_argument("--data", default=None, help="the shared data folder (default: ../shared/data)")
    args = parser.parse_args()
    trackd = find_trackd(args.trackd)
    here = os.path.dirname(os.path.abspath(__file__))
    data = args.data or os.path.normpath(os.path.join(here, "..", "..", "..", "shared", "data"))
    if not os.path.isdir(data):
        data = "/work/shared/data"
    if not os.path.isdir(data):
        sys.exit(f"shared data folder not found ({data}): cannot cross-check on real scans")

    odometry = os.path.join(data, "kitti-odometry-00", "000000.bin")
    raw = os.path.join(data, "kitti-raw-22", "0000000000.pcd")
    tracking = os.path.join(data, "kitti-tracking-0000-first40", "training", "velodyne", "0000")

    ok = True
    with tempfile.TemporaryDirectory() as workdir:
        # Whole scans, ground included: dense, so a small radius keeps scikit-learn's memory sane.
        ok &= check(trackd, "odometry-00/000000.bin (all points)", odometry, read_bin(odometry), 0.3, 10, workdir)
        ok &= check(trackd, "raw-22/0000000000.pcd (all points)", raw, read_pcd(raw), 0.25, 5, workdir)
        # Above-road points of tracking scans, with the pipeline's radius and others.
        for frame, params in (("000000", [(0.7, 4), (0.5, 10), (1.0, 2)]), ("000020", [(0.7, 4), (0.35, 3)])):
            xyz = above_road(read_bin(os.path.join(tracking, frame + ".bin"))).astype("<f4")
            path = os.path.join(workdir, f"tracking-{frame}-above-road.xyz")
            xyz.tofile(path)
            for eps, min_points in params:
                ok &= check(trackd, f"tracking-0000/{frame} above road (.xyz)", path, xyz, eps, min_points, workdir)
    print("all identical" if ok else "MISMATCHES FOUND")
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())
