#!/usr/bin/env bash
# The README's picture of `dem2d animate`'s HTML player (figures/player_hopper.png): the hopper
# of segment walls (cases/hopper_segments.json) at its last frame, the grains coloured by the
# normal contact force on each, the contact network drawn (the arch over the outlet), as headless
# Chromium shows the page. Needs Debian's chromium; run from the repository after
# `cargo build --release`. About 20 s (18 s measured; the run 10–13 s).
set -euo pipefail
cd "$(dirname "$0")/../.."
run=target/player-figure
target/release/dem2d run cases/hopper_segments.json --out "$run" --contacts --quiet --overwrite
target/release/dem2d animate "$run"
profile=$(mktemp -d)
trap 'rm -rf "$profile"' EXIT
chromium --headless --no-sandbox --disable-gpu --disable-background-networking \
  --disable-component-update --disable-sync --no-first-run --hide-scrollbars \
  --user-data-dir="$profile" --force-device-scale-factor=1 --window-size=1000,762 \
  --screenshot=figures/player_hopper.png \
  "file://$PWD/$run/animation.html#frame=last&color=force&network&size=1000x700" 2> /dev/null
echo figures/player_hopper.png
