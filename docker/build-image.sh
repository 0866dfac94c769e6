#!/usr/bin/env bash
# Builds the trackd container image FROM scratch, pulling nothing: the host-built `trackd` and
# `trackctl`, the shared libraries ldd resolves for them (dynamic loader included), a non-root
# user, a writable /tmp and /var/lib/trackd.
#
# Usage: docker/build-image.sh [PROFILE_DIR] [TAG]
#   PROFILE_DIR  cargo profile directory holding the binaries
#                (default: ${CARGO_TARGET_DIR:-target}/release; CI passes target/debug)
#   TAG          image tag (default: $TRACKD_IMAGE, else trackd:local)
#
#   cargo build --release --bins && docker/build-image.sh
set -euo pipefail

repo=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
profile_dir=${1:-${CARGO_TARGET_DIR:-$repo/target}/release}
tag=${2:-${TRACKD_IMAGE:-trackd:local}}
binaries=(trackd trackctl)
uid=10001

die() {
    echo "build-image: $*" >&2
    exit 1
}

for bin in "${binaries[@]}"; do
    [[ -x "$profile_dir/$bin" ]] ||
        die "$profile_dir/$bin is missing: build it first (cargo build --release --bins, or pass the profile dir, e.g. target/debug)"
done

context=$(mktemp -d "${TMPDIR:-/tmp}/trackd-image.XXXXXX")
trap 'rm -rf "$context"' EXIT
rootfs=$context/rootfs
mkdir -p "$rootfs/usr/local/bin" "$rootfs/etc" "$rootfs/tmp" "$context/data"
chmod 1777 "$rootfs/tmp"

# The binaries and every library they load, at the path the loader will look for it.
libraries=()
for bin in "${binaries[@]}"; do
    cp "$profile_dir/$bin" "$rootfs/usr/local/bin/$bin"
    ldd_out=$(ldd "$profile_dir/$bin" 2>&1) || {
        [[ $ldd_out == *"not a dynamic executable"* || $ldd_out == *"statically linked"* ]] ||
            die "ldd $bin failed: $ldd_out"
        continue
    }
    if grep -q 'not found' <<<"$ldd_out"; then
        die "$bin needs libraries this host lacks:"$'\n'"$ldd_out"
    fi
    # "libc.so.6 => /lib/x86_64-linux-gnu/libc.so.6 (0x...)" and "/lib64/ld-linux-x86-64.so.2 (0x...)"
    while read -r lib; do
        libraries+=("$lib")
    done < <(awk '$2 == "=>" && $3 ~ /^\// { print $3 } $1 ~ /^\// { print $1 }' <<<"$ldd_out")
done
mapfile -t libraries < <(printf '%s\n' "${libraries[@]}" | sort -u)
for lib in "${libraries[@]}"; do
    mkdir -p "$rootfs$(dirname "$lib")"
    cp -L "$lib" "$rootfs$lib"
done

cat >"$rootfs/etc/passwd" <<EOF
root:x:0:0:root:/root:/sbin/nologin
trackd:x:$uid:$uid:trackd:/var/lib/trackd:/sbin/nologin
nobody:x:65534:65534:nobody:/nonexistent:/sbin/nologin
EOF
cat >"$rootfs/etc/group" <<EOF
root:x:0:
trackd:x:$uid:
nogroup:x:65534:
EOF
# Names resolve from /etc/hosts, then Docker's DNS (service names on a compose network).
echo 'hosts: files dns' >"$rootfs/etc/nsswitch.conf"

cp "$repo/docker/Dockerfile" "$context/Dockerfile"
commit=$(git -C "$repo" rev-parse --short HEAD 2>/dev/null || echo unknown)
echo "build-image: $tag from $profile_dir (commit $commit, $(du -sh "$rootfs" | cut -f1) rootfs, ${#libraries[@]} libraries: ${libraries[*]})"
previous=$(docker image inspect --format '{{.Id}}' "$tag" 2>/dev/null || true)
docker build --quiet \
    --label "org.opencontainers.image.title=trackd" \
    --label "org.opencontainers.image.revision=$commit" \
    --label "trackd.profile-dir=$(basename "$profile_dir")" \
    --tag "$tag" "$context"
# The image this tag named before, now untagged: removed unless something still uses it.
current=$(docker image inspect --format '{{.Id}}' "$tag")
if [[ -n $previous && $previous != "$current" ]]; then
    docker image rm "$previous" >/dev/null 2>&1 || true
fi
