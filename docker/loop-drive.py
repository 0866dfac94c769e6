#!/usr/bin/env python3
"""Lays out a KITTI raw drive replayed in laps, so a 10 Hz sensor feed can outlast its drive.

    loop-drive.py SRC_DRIVE DST_DRIVE --seconds 600 [--gap 2.0]

DST_DRIVE gets velodyne_points/ and oxts/ whose data files are hard links to SRC_DRIVE's (no
copy), lap after lap, and whose timestamps keep increasing: lap k is shifted by k times (the
drive's duration + one frame period + GAP seconds). The GAP is longer than the pose filter's
largest prediction gap, so each lap starts like a GPS outage ended: the filter re-initialises
from the next fix instead of seeing the vehicle jump back to its start. Used by
docker/fleet-test.sh; the drive itself comes from `trackd sim`.
"""

import argparse
import datetime
import math
import os
import pathlib
import shutil
import sys

FORMAT = "%Y-%m-%d %H:%M:%S"


def read_stamps(path):
    """KITTI timestamps ("2011-09-26 13:02:25.000950813") as integer nanoseconds."""
    stamps = []
    for number, line in enumerate(path.read_text().splitlines(), 1):
        line = line.strip()
        if not line:
            continue
        whole, _, fraction = line.partition(".")
        try:
            seconds = datetime.datetime.strptime(whole, FORMAT).replace(
                tzinfo=datetime.timezone.utc
            )
            nanos = int((fraction + "000000000")[:9]) if fraction else 0
        except ValueError as e:
            sys.exit(f"{path}:{number}: not a KITTI timestamp: {line!r} ({e})")
        stamps.append(int(seconds.timestamp()) * 1_000_000_000 + nanos)
    return stamps


def format_stamp(nanos):
    seconds, fraction = divmod(nanos, 1_000_000_000)
    when = datetime.datetime.fromtimestamp(seconds, datetime.timezone.utc)
    return f"{when.strftime(FORMAT)}.{fraction:09d}"


def data_files(folder, suffix):
    files = sorted(p for p in folder.iterdir() if p.suffix == suffix)
    if not files:
        sys.exit(f"{folder}: no {suffix} files")
    return files


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("src", type=pathlib.Path, help="a KITTI raw *_sync drive folder")
    parser.add_argument("dst", type=pathlib.Path, help="the looped drive to create")
    parser.add_argument(
        "--seconds", type=float, default=600, help="scan time to cover (default 600)"
    )
    parser.add_argument(
        "--gap", type=float, default=2.0, help="seconds of silence between laps (default 2)"
    )
    args = parser.parse_args()

    scans = data_files(args.src / "velodyne_points" / "data", ".bin")
    packets = data_files(args.src / "oxts" / "data", ".txt")
    stamps = read_stamps(args.src / "velodyne_points" / "timestamps.txt")
    if not len(scans) == len(packets) == len(stamps) or len(scans) < 2:
        sys.exit(
            f"{args.src}: {len(scans)} scans, {len(packets)} OXTS packets, {len(stamps)} "
            "timestamps: need as many of each, at least 2"
        )
    period = (stamps[-1] - stamps[0]) // (len(stamps) - 1)
    lap = stamps[-1] - stamps[0] + period + int(args.gap * 1e9)
    laps = max(1, math.ceil(args.seconds * 1e9 / (len(stamps) * period)))

    scan_dir = args.dst / "velodyne_points" / "data"
    oxts_dir = args.dst / "oxts" / "data"
    scan_dir.mkdir(parents=True)
    oxts_dir.mkdir(parents=True)
    lines = []
    for k in range(laps):
        for i, (scan, packet, stamp) in enumerate(zip(scans, packets, stamps)):
            n = k * len(scans) + i
            os.link(scan, scan_dir / f"{n:010d}.bin")
            os.link(packet, oxts_dir / f"{n:010d}.txt")
            lines.append(format_stamp(stamp + k * lap))
    text = "\n".join(lines) + "\n"
    (args.dst / "velodyne_points" / "timestamps.txt").write_text(text)
    (args.dst / "oxts" / "timestamps.txt").write_text(text)
    dataformat = args.src / "oxts" / "dataformat.txt"
    if dataformat.is_file():
        shutil.copyfile(dataformat, args.dst / "oxts" / "dataformat.txt")
    print(
        f"{args.dst}: {laps} laps of {len(scans)} scans ({len(lines)} scans, "
        f"{len(lines) * period / 1e9:.0f} s at {1e9 / period:.1f} Hz)"
    )


if __name__ == "__main__":
    main()
