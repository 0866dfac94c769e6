#!/usr/bin/env bash
# The fleet of docker/compose.yml, end to end: a Zenoh router and three vehicles in containers
# built FROM scratch, each fed its own simulated drive of one shared world.
#
# Usage: docker/fleet-test.sh [PROFILE_DIR]   (default: ${CARGO_TARGET_DIR:-target}/release)
#
#   cargo build --workspace --bins && docker/fleet-test.sh target/debug
#
# Builds the image from PROFILE_DIR's trackd and trackctl (docker/build-image.sh), simulates
# the drives on the host (trackd sim --vehicles 3), starts the fleet and checks over REST:
#   1. sharing: every vehicle's fleet view holds objects only other vehicles see;
#   2. partition: vehicle-3 cut off the network (docker network disconnect) expires from the
#      others within the TTL, and comes back once reconnected, with no restart;
#   3. crash: after docker kill of vehicle-2 the others keep serving and drop its objects; a
#      restarted vehicle-2 rejoins;
#   4. router loss: no sharing, each vehicle still tracks; sharing resumes when it returns.
# Prints a report with timings. Cleans up what it started (containers, network, volumes,
# temporary files; the image too with TRACKD_FLEET_RMI=1), also on failure, when it prints the
# containers' logs.
#
# Environment: TRACKD_IMAGE (tag to build, default trackd:fleet-test), TRACKD_FLEET_RMI=1,
# TRACKD_FLEET_FRAMES (frames per simulated drive, replayed in laps; default 100),
# TRACKD_FLEET_SCENARIO (default paper), TRACKD_FLEET_SEED (default 7).
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(dirname "$here")
profile_arg=${1:-${CARGO_TARGET_DIR:-$repo/target}/release}
profile_dir=$(cd "$profile_arg" 2>/dev/null && pwd) || {
    echo "fleet-test: no profile directory $profile_arg (build first: cargo build --workspace --bins)" >&2
    exit 1
}
frames=${TRACKD_FLEET_FRAMES:-100}
scenario=${TRACKD_FLEET_SCENARIO:-paper}
seed=${TRACKD_FLEET_SEED:-7}
vehicles=(vehicle-1 vehicle-2 vehicle-3)
services=(router "${vehicles[@]}" sensor-1 sensor-2 sensor-3)

export TRACKD_IMAGE=${TRACKD_IMAGE:-trackd:fleet-test}
if command -v docker-compose >/dev/null; then
    compose_cmd=(docker-compose)
elif docker compose version >/dev/null 2>&1; then
    compose_cmd=(docker compose)
else
    echo "fleet-test: needs docker-compose (or the docker compose plugin)" >&2
    exit 1
fi
command -v python3 >/dev/null || {
    echo "fleet-test: needs python3" >&2
    exit 1
}

work=$(mktemp -d "${TMPDIR:-/tmp}/trackd-fleet.XXXXXX")
project=trackdfleet$$
compose() { "${compose_cmd[@]}" --project-name "$project" --file "$here/compose.yml" "$@"; }

# Everything compose.yml interpolates, set before the first compose call (cleanup needs it).
for k in 1 2 3; do
    export "TRACKD_DRIVE_$k=$work/loops/vehicle-$k"
done
read -r TRACKD_PORT_1 TRACKD_PORT_2 TRACKD_PORT_3 < <(python3 -c '
import socket
socks = [socket.socket() for _ in range(3)]
for s in socks:
    s.bind(("127.0.0.1", 0))
print(*(s.getsockname()[1] for s in socks))')
export TRACKD_PORT_1 TRACKD_PORT_2 TRACKD_PORT_3 TRACKD_ORIGIN=0,0,0
declare -A port=([vehicle-1]=$TRACKD_PORT_1 [vehicle-2]=$TRACKD_PORT_2 [vehicle-3]=$TRACKD_PORT_3)
declare -A cid=()
ttl_ms=$(python3 -c 'import sys, tomllib; print(tomllib.load(open(sys.argv[1], "rb"))["fleet"]["ttl_ms"])' "$here/trackd.toml")
# Expiry is measured from the cut to the moment the objects leave the last view for good
# (then out for $hold_s s: remote objects also blink out between super frames when the host is
# too slow for 10 Hz); probes and scheduling add at most $expiry_slack_ms.
expiry_slack_ms=2000
hold_s=3

ms() { echo $((${EPOCHREALTIME/./} / 1000)); }
seconds() { printf '%d.%01d s' $(($1 / 1000)) $(($1 % 1000 / 100)); }
say() { echo "fleet-test: $*" >&2; }
report=()
record() { report+=("$*"); }

logs_dumped=0
dump_logs() {
    ((logs_dumped)) && return
    logs_dumped=1
    echo "===== what each vehicle sees =====" >&2
    for v in "${vehicles[@]}"; do
        echo "$v: $(python3 "$here/fleet-watch.py" look "${port[$v]}")" >&2
    done
    for s in "${services[@]}"; do
        echo "===== logs of $s (last 60 lines) =====" >&2
        compose logs --no-color --tail=60 "$s" >&2 2>&1 || true
    done
}

fail() {
    echo >&2
    echo "fleet-test: FAILED: $*" >&2
    dump_logs
    exit 1
}

cleanup() {
    local status=$?
    set +e
    ((status != 0)) && dump_logs
    say "cleaning up"
    compose down --volumes --remove-orphans --timeout 3 >/dev/null 2>&1
    rm -rf "$work"
    if [[ ${TRACKD_FLEET_RMI:-0} == 1 ]]; then
        docker image rm "$TRACKD_IMAGE" >/dev/null 2>&1
    fi
    exit "$status"
}
trap cleanup EXIT
trap 'exit 130' INT
trap 'exit 143' TERM

# look VEHICLE: sets up, frames, tracks, objects, own, only_others, sources and only_from.
look() {
    up=0 frames=0 tracks=0 objects=0 own=0 only_others=0 sources="" only_from=""
    eval "$(python3 "$here/fleet-watch.py" look "${port[$1]}")"
}
ports_of() {
    local v
    for v in "$@"; do echo "${port[$v]}"; done
}

# wait_until TIMEOUT_S WHAT COMMAND...: polls COMMAND until it succeeds; sets waited_ms.
wait_until() {
    local timeout_ms=$(($1 * 1000)) what=$2 start
    shift 2
    start=$(ms)
    until "$@"; do
        (($(ms) - start < timeout_ms)) || fail "$what: not within $timeout_ms ms"
        sleep 0.25
    done
    waited_ms=$(($(ms) - start))
}
# tracking_past V FRAMES: V answers and has processed more than FRAMES frames.
tracking_past() {
    look "$1"
    ((up && frames > $2))
}
# tracks_past V FRAMES: that, and V holds tracks of its own.
tracks_past() {
    tracking_past "$1" "$2" && ((tracks > 0))
}
# shares TIMEOUT_S WHAT VEHICLES...: each of them holds objects only another one sees, from
# every other one (seen over the polls); sets waited_ms.
shares() {
    local timeout_s=$1 what=$2
    shift 2
    # shellcheck disable=SC2046
    waited_ms=$(python3 "$here/fleet-watch.py" shares --timeout "$timeout_s" $(ports_of "$@")) ||
        fail "$what"
}
# gone TIMEOUT_S WHAT (--vehicle ID | --everyone) VEHICLES...: the objects of ID (of every other
# vehicle) leave the views of VEHICLES for good; sets waited_ms.
gone() {
    local timeout_s=$1 what=$2 who=("$3")
    shift 3
    [[ ${who[0]} == --vehicle ]] && {
        who+=("$1")
        shift
    }
    # shellcheck disable=SC2046
    waited_ms=$(python3 "$here/fleet-watch.py" gone --timeout "$timeout_s" --hold "$hold_s" \
        "${who[@]}" $(ports_of "$@")) || fail "$what"
}
started_at() { docker inspect --format '{{.State.StartedAt}} restarts={{.RestartCount}}' "$1"; }
summary() {
    look "$1"
    echo "$1 now: frames=$frames tracks=$tracks fused objects=$objects: $own its own, $only_others only others see (from ${only_from:-nobody}); sources besides itself: ${sources:-none}"
}

t0=$(ms)

# ---- the image --------------------------------------------------------------------------
say "building $TRACKD_IMAGE from $profile_dir"
t=$(ms)
"$here/build-image.sh" "$profile_dir" "$TRACKD_IMAGE" >"$work/build.log" 2>&1 || {
    cat "$work/build.log" >&2
    fail "docker/build-image.sh failed"
}
image_ms=$(($(ms) - t))
image_size=$(docker image inspect --format '{{.Size}}' "$TRACKD_IMAGE")
image_user=$(docker image inspect --format '{{.Config.User}}' "$TRACKD_IMAGE")
record "image   $TRACKD_IMAGE FROM scratch, $((image_size / 1000000)) MB, user $image_user, built in $(seconds "$image_ms") from $profile_dir"

# ---- the drives -------------------------------------------------------------------------
say "simulating $scenario: 3 vehicles x $frames frames (seed $seed)"
t=$(ms)
"$profile_dir/trackd" sim --scenario "$scenario" --frames "$frames" --seed "$seed" \
    --vehicles 3 --out "$work/sim" >"$work/sim.log" 2>&1 || {
    cat "$work/sim.log" >&2
    fail "trackd sim failed"
}
mapfile -t drives < <(find "$work/sim" -mindepth 2 -maxdepth 2 -type d -name '*_drive_*_sync' | sort)
((${#drives[@]} == 3)) || fail "trackd sim wrote ${#drives[@]} drives, expected 3: ${drives[*]}"
for k in 1 2 3; do
    # 10 minutes of scans: the sensors outlast the test, which never takes that long.
    python3 "$here/loop-drive.py" "${drives[k - 1]}" "$work/loops/vehicle-$k" --seconds 600 >/dev/null
done
# The fleet origin: the first GPS fix of drive 1 (every vehicle must share one).
read -r lat lon alt _ <"${drives[0]}/oxts/data/0000000000.txt"
export TRACKD_ORIGIN=$lat,$lon,$alt
sim_ms=$(($(ms) - t))
record "drives  $scenario, 3 x $frames frames ($((frames / 10)) s laps, replayed at 10 Hz), simulated in $(seconds "$sim_ms"); origin $TRACKD_ORIGIN"

# ---- the fleet --------------------------------------------------------------------------
say "starting the fleet (project $project)"
t=$(ms)
compose up --detach >"$work/up.log" 2>&1 || {
    cat "$work/up.log" >&2
    fail "docker-compose up failed"
}
for s in "${services[@]}"; do
    cid[$s]=$(compose ps -q "$s")
    [[ -n ${cid[$s]} ]] || fail "no container for $s"
done
network=$(docker inspect --format '{{range $k, $v := .NetworkSettings.Networks}}{{$k}}{{end}}' "${cid[router]}")
for v in "${vehicles[@]}"; do
    wait_until 60 "$v healthy" tracking_past "$v" 0
done
up_ms=$(($(ms) - t))
health=$(for v in "${vehicles[@]}"; do docker inspect --format '{{.State.Health.Status}}' "${cid[$v]}"; done | sort | uniq -c | xargs)
record "fleet   router + 3 vehicles (Zenoh client mode) + 3 sensors on network $network; tracking after $(seconds "$up_ms"); health: $health"

# ---- 1. sharing -------------------------------------------------------------------------
say "1. sharing"
shares 90 "1. every vehicle holds objects only another one sees, from each of the others" "${vehicles[@]}"
record "[ok] 1 sharing: every vehicle held objects only another one sees, from each of the others, $(seconds "$waited_ms") after all were tracking"
for v in "${vehicles[@]}"; do record "         $(summary "$v")"; done

# ---- 2. partition -----------------------------------------------------------------------
say "2. partition of vehicle-3"
before=$(started_at "${cid[vehicle-3]}")
look vehicle-3
frames_cut=$frames
docker network disconnect "$network" "${cid[vehicle-3]}"
gone 30 "2. vehicle-3's objects expire from vehicle-1 and vehicle-2" --vehicle vehicle-3 vehicle-1 vehicle-2
expired_ms=$waited_ms
((expired_ms <= ttl_ms + expiry_slack_ms)) ||
    fail "2. vehicle-3 expired after $expired_ms ms, more than the TTL ($ttl_ms ms) + $expiry_slack_ms ms"
docker network connect --alias vehicle-3 "$network" "${cid[vehicle-3]}"
shares 120 "2. vehicle-3 shares with vehicle-1 and vehicle-2 again" "${vehicles[@]}"
back_ms=$waited_ms
after=$(started_at "${cid[vehicle-3]}")
[[ $before == "$after" ]] || fail "2. vehicle-3 restarted: $before -> $after"
look vehicle-3
((frames > frames_cut)) || fail "2. vehicle-3 stopped tracking while cut off (frames $frames_cut -> $frames)"
record "[ok] 2 partition: vehicle-3 cut off: its objects left the others' views $(seconds "$expired_ms") after the cut (TTL $(seconds "$ttl_ms")) and stayed out; reconnected: shared both ways again after $(seconds "$back_ms"), not restarted (started $after); it tracked on alone (frames $frames_cut -> $frames)"

# ---- 3. crash ---------------------------------------------------------------------------
say "3. crash of vehicle-2"
look vehicle-1
f1=$frames
look vehicle-3
f3=$frames
docker kill "${cid[vehicle-2]}" >/dev/null
gone 30 "3. vehicle-2's objects expire from vehicle-1 and vehicle-3" --vehicle vehicle-2 vehicle-1 vehicle-3
gone_ms=$waited_ms
((gone_ms <= ttl_ms + expiry_slack_ms)) ||
    fail "3. vehicle-2 expired after $gone_ms ms, more than the TTL ($ttl_ms ms) + $expiry_slack_ms ms"
wait_until 60 "3. vehicle-1 keeps tracking" tracks_past vehicle-1 $((f1 + 10))
wait_until 60 "3. vehicle-3 keeps tracking" tracks_past vehicle-3 $((f3 + 10))
shares 60 "3. vehicle-1 and vehicle-3 still share" vehicle-1 vehicle-3
look vehicle-1
f1="$f1 -> $frames"
look vehicle-3
f3="$f3 -> $frames"
docker start "${cid[vehicle-2]}" >/dev/null
wait_until 60 "3. vehicle-2 serves again" tracking_past vehicle-2 -1
# Its sensor shares its network namespace: it lost the service with it, and starts again.
docker restart --time 1 "${cid[sensor-2]}" >/dev/null
shares 120 "3. vehicle-2 rejoins the fleet" "${vehicles[@]}"
rejoin_ms=$waited_ms
record "[ok] 3 crash: vehicle-2 killed: its objects left the others' views after $(seconds "$gone_ms"); vehicle-1 (frames $f1) and vehicle-3 (frames $f3) kept tracking and sharing; restarted with its sensor: rejoined after $(seconds "$rejoin_ms")"

# ---- 4. router loss ---------------------------------------------------------------------
say "4. router loss"
declare -A f=()
for v in "${vehicles[@]}"; do
    look "$v"
    f[$v]=$frames
done
docker kill "${cid[router]}" >/dev/null
gone 30 "4. no sharing without the router" --everyone "${vehicles[@]}"
alone_ms=$waited_ms
for v in "${vehicles[@]}"; do
    wait_until 60 "4. $v keeps tracking without the router" tracks_past "$v" $((f[$v] + 10))
done
tracked=$(for v in "${vehicles[@]}"; do
    look "$v"
    echo "$v ${f[$v]} -> $frames"
done | paste -sd, | sed 's/,/, /g')
docker start "${cid[router]}" >/dev/null
shares 120 "4. sharing resumes with the router back" "${vehicles[@]}"
resume_ms=$waited_ms
record "[ok] 4 router loss: router killed: no vehicle held another's objects after $(seconds "$alone_ms"), each kept tracking alone (frames $tracked); router restarted: sharing resumed after $(seconds "$resume_ms")"
for v in "${vehicles[@]}"; do record "         $(summary "$v")"; done

total_ms=$(($(ms) - t0))
echo
echo "trackd fleet test: PASSED in $(seconds "$total_ms")"
printf '  %s\n' "${report[@]}"
