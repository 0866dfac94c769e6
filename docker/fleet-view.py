#!/usr/bin/env python3
"""Prints what one trackd vehicle sees of the fleet, as shell assignments for fleet-test.sh.

    fleet-view.py PORT     (the vehicle's REST API on 127.0.0.1:PORT)

    up=1 vehicle=vehicle-1 frames=412 tracks=7 objects=11 own=7 only_others=4
    sources='vehicle-2 vehicle-3'

`sources`: the other vehicles that are a source of at least one object of GET /v1/fleet/objects;
`only_others`: objects whose sources do not include this vehicle. `up=0` (and nothing else)
when the API does not answer 200 with the expected JSON.
"""

import json
import shlex
import sys
import urllib.request


def get(port, path):
    with urllib.request.urlopen(f"http://127.0.0.1:{port}{path}", timeout=3) as answer:
        return json.load(answer)


def main():
    if len(sys.argv) != 2:
        sys.exit(__doc__)
    port = sys.argv[1]
    try:
        health = get(port, "/healthz")
        tracks = get(port, "/v1/tracks")["tracks"]
        objects = get(port, "/v1/fleet/objects")["objects"]
        me = health["vehicle"]
        frames = int(health["frames"])
        sources = sorted({s for o in objects for s in o["sources"] if s != me})
        only_others = sum(1 for o in objects if me not in o["sources"])
        own = len(objects) - only_others
    except (OSError, ValueError, KeyError, TypeError):
        print("up=0")
        return
    print(
        f"up=1 vehicle={shlex.quote(me)} frames={frames} tracks={len(tracks)} "
        f"objects={len(objects)} own={own} only_others={only_others} "
        f"sources={shlex.quote(' '.join(sources))}"
    )


if __name__ == "__main__":
    main()
