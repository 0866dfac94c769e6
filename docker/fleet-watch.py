#!/usr/bin/env python3
"""Watches the fleet views of trackd vehicles (REST APIs on 127.0.0.1) for docker/fleet-test.sh.

    fleet-watch.py look PORT
        One vehicle, as shell assignments:
        up=1 vehicle=vehicle-1 frames=412 tracks=7 objects=11 own=7 only_others=4
        sources='vehicle-2 vehicle-3' only_from='vehicle-2'
        (up=0 and nothing else when it does not answer).
    fleet-watch.py shares --timeout S PORT...
        Waits until each vehicle has held, at some poll, objects that only another one sees, from
        every other one of them. Prints the milliseconds it took.
    fleet-watch.py gone --timeout S --hold S (--vehicle ID | --everyone) PORT...
        Waits until no object of vehicle ID (of any other vehicle with --everyone) is in any of
        their views, and has stayed out for --hold seconds while they kept answering. Prints the
        milliseconds from the start to the moment the last of them lost it for good.

`sources`: the other vehicles that are a source of some object of GET /v1/fleet/objects;
`only_from`: those that are a source of an object this vehicle does not see itself. Polls every
250 ms; exits 1 with what it last saw on a timeout, or when a vehicle stops answering.
"""

import argparse
import json
import shlex
import sys
import time
import urllib.request

POLL_S = 0.25


def get(port, path):
    with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=3) as answer:
        return json.load(answer)


class View:
    """What one vehicle's API says at one moment."""

    def __init__(self, port):
        health = get(port, "/healthz")
        objects = get(port, "/v1/fleet/objects")["objects"]
        self.tracks = len(get(port, "/v1/tracks")["tracks"])
        self.vehicle = health["vehicle"]
        self.frames = int(health["frames"])
        self.objects = len(objects)
        me = self.vehicle
        self.sources = sorted({s for o in objects for s in o["sources"] if s != me})
        others_only = [o for o in objects if me not in o["sources"]]
        self.only_others = len(others_only)
        self.only_from = sorted({s for o in others_only for s in o["sources"]})

    def line(self):
        return (
            f"{self.vehicle}: frames={self.frames} tracks={self.tracks} objects={self.objects} "
            f"only-others={self.only_others} sources=[{' '.join(self.sources)}] "
            f"only-from=[{' '.join(self.only_from)}]"
        )


def view_or_none(port):
    try:
        return View(port)
    except (OSError, ValueError, KeyError, TypeError):
        return None


def look(args):
    v = view_or_none(args.port)
    if v is None:
        print("up=0")
        return 0
    q = shlex.quote
    print(
        f"up=1 vehicle={q(v.vehicle)} frames={v.frames} tracks={v.tracks} "
        f"objects={v.objects} own={v.objects - v.only_others} only_others={v.only_others} "
        f"sources={q(' '.join(v.sources))} only_from={q(' '.join(v.only_from))}"
    )
    return 0


def poll(ports, require_up):
    views = {port: view_or_none(port) for port in ports}
    down = [port for port, v in views.items() if v is None]
    if down and require_up:
        raise Stop(f"127.0.0.1:{', '.join(map(str, down))} stopped answering")
    return views


class Stop(Exception):
    """The wait failed."""


def shares(args):
    start = time.monotonic()
    seen = set()
    views = {}
    while True:
        views = poll(args.ports, require_up=False)
        up = {p: v for p, v in views.items() if v is not None}
        ids = {v.vehicle for v in up.values()}
        for v in up.values():
            seen.update((v.vehicle, w) for w in v.only_from)
        if len(up) == len(args.ports):
            wanted = {(a, b) for a in ids for b in ids if a != b}
            if wanted <= seen:
                return round((time.monotonic() - start) * 1000)
        if time.monotonic() - start > args.timeout:
            missing = sorted(
                f"{a} <- {b}" for a in ids for b in ids if a != b and (a, b) not in seen
            )
            raise Stop(
                f"never seen: {', '.join(missing) or 'all vehicles answering'}; last views:\n"
                + describe(views)
            )
        time.sleep(POLL_S)


def gone(args):
    start = time.monotonic()
    lost_at = {}  # port -> when the vehicle(s) left its view, while still out
    views = {}
    while True:
        now = time.monotonic()
        views = poll(args.ports, require_up=True)
        for port, v in views.items():
            present = v.sources if args.everyone else [s for s in v.sources if s == args.vehicle]
            if present:
                lost_at.pop(port, None)
            else:
                lost_at.setdefault(port, now)
        if len(lost_at) == len(args.ports) and now - max(lost_at.values()) >= args.hold:
            return round((max(lost_at.values()) - start) * 1000)
        if now - start > args.timeout:
            who = "any other vehicle" if args.everyone else args.vehicle
            raise Stop(
                f"objects of {who} did not stay out of every view for {args.hold} s; "
                "last views:\n" + describe(views)
            )
        time.sleep(POLL_S)


def describe(views):
    return "\n".join(
        f"  127.0.0.1:{port}: {v.line() if v else 'not answering'}" for port, v in views.items()
    )


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    commands = parser.add_subparsers(dest="command", required=True)
    p = commands.add_parser("look")
    p.add_argument("port", type=int)
    p.set_defaults(run=look)
    p = commands.add_parser("shares")
    p.add_argument("--timeout", type=float, required=True)
    p.add_argument("ports", type=int, nargs="+")
    p.set_defaults(run=shares)
    p = commands.add_parser("gone")
    p.add_argument("--timeout", type=float, required=True)
    p.add_argument("--hold", type=float, required=True)
    who = p.add_mutually_exclusive_group(required=True)
    who.add_argument("--vehicle")
    who.add_argument("--everyone", action="store_true")
    p.add_argument("ports", type=int, nargs="+")
    p.set_defaults(run=gone)
    args = parser.parse_args()
    try:
        result = args.run(args)
    except Stop as e:
        print(f"fleet-watch {args.command}: {e}", file=sys.stderr)
        return 1
    if args.command != "look":
        print(result)
    return 0


if __name__ == "__main__":
    sys.exit(main())
