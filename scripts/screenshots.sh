#!/usr/bin/env bash
# Starts the native viewer under Xvfb and the web viewer in headless Chromium, takes a
# screenshot of each, checks that neither is blank, and measures the frame rate.
#
#   scripts/screenshots.sh [OUT_DIR]      (default: docs)
#
# Writes OUT_DIR/viewer-native.png, OUT_DIR/viewer-explorer.png, OUT_DIR/viewer-drum.png and
# OUT_DIR/viewer-web.png.
# Needs (installed here if missing, as root): xvfb, imagemagick, chromium, Mesa's software
# OpenGL. Prints the measured frame rates; they are also written to OUT_DIR/bench/viewer.txt.
set -euo pipefail
cd "$(dirname "$0")/.."
out=${1:-docs}
mkdir -p "$out/bench"

need=()
command -v Xvfb >/dev/null || need+=(xvfb)
command -v import >/dev/null || need+=(imagemagick)
command -v chromium >/dev/null || need+=(chromium)
compgen -G "/usr/lib/*/dri/swrast_dri.so" >/dev/null || need+=(libgl1-mesa-dri libegl1 libgl1)
if [ ${#need[@]} -gt 0 ]; then
  echo "installing ${need[*]}" >&2
  apt-get update -qq && DEBIAN_FRONTEND=noninteractive apt-get install -y -qq "${need[@]}" >/dev/null
fi

cargo build --release -p supergrain-cli
sg=target/release/supergrain

# A free display number.
d=90
while [ -e "/tmp/.X11-unix/X$d" ] || [ -e "/tmp/.X$d-lock" ]; do d=$((d + 1)); done
Xvfb ":$d" -screen 0 1280x800x24 -nolisten tcp >/dev/null 2>&1 &
xvfb=$!
server=""
work=$(mktemp -d)
cleanup() {
  kill "$xvfb" 2>/dev/null || true
  if [ -n "$server" ]; then kill "$server" 2>/dev/null || true; fi
  rm -rf "$work"
}
trap cleanup EXIT
sleep 1
export DISPLAY=":$d"

# Not blank: the picture's grey levels spread (a blank or one-colour window has none).
not_blank() {
  local spread
  spread=$(convert "$1" -colorspace gray -format "%[fx:standard_deviation]" info:)
  awk -v s="$spread" -v f="$1" 'BEGIN { if (s < 0.05) { print f " looks blank (spread " s ")"; exit 1 } print f ": spread " s }'
}

# 1. The native viewer on the mixed preset: a screenshot after 8 s.
"$sg" view --preset mixed --speed 4 --quit-after 10 >/dev/null &
viewer=$!
sleep 8
import -window root "$out/viewer-native.png"
wait "$viewer"
not_blank "$out/viewer-native.png"

# The collision explorer (B stays at its starting place: no mouse under Xvfb).
"$sg" view --explorer --quit-after 5 >/dev/null &
viewer=$!
sleep 3
import -window root "$out/viewer-explorer.png"
wait "$viewer"
not_blank "$out/viewer-explorer.png"

# The rotating drum: a boundary turning, and the scene's surface measure live in the panel.
"$sg" view examples/scenes/drum.toml --speed 2 --quit-after 14 >/dev/null &
viewer=$!
sleep 12
import -window root "$out/viewer-drum.png"
wait "$viewer"
not_blank "$out/viewer-drum.png"

# 2. The frame rate on the 1,000-grain example while it pours (the on-screen counter, also
# printed once a second with --log-fps), over 60 s.
"$sg" view examples/scenes/pour-1000.toml --log-fps --quit-after 60 > "$work/fps.txt" &
viewer=$!
sleep 40
import -window root "$out/viewer-pour-1000.png"
wait "$viewer"
# The mixed preset flat out (50 steps per frame, more than either keeps up with) for 40 s:
# steps done over seconds since start, natively and in the browser.
native_mixed=$("$sg" view --preset mixed --speed 50 --log-fps --quit-after 40 | tail -n 1)

# 3. The web viewer in headless Chromium.
scripts/build-web.sh
port=8123
python3 -m http.server "$port" --directory web --bind 127.0.0.1 >/dev/null 2>&1 &
server=$!
sleep 1
chrome=(chromium --headless --no-sandbox --no-first-run --disable-background-networking
  --disable-component-update --disable-sync --disable-quic --use-angle=swiftshader
  --enable-unsafe-swiftshader --user-data-dir="$work/profile" --window-size=1280,800)
timeout 60 "${chrome[@]}" --virtual-time-budget=8000 --screenshot="$out/viewer-web.png" \
  "http://127.0.0.1:$port/index.html?speed=4" 2>/dev/null
not_blank "$out/viewer-web.png"
# The page's Save buttons offer a state that the native tools read, and a PNG.
if command -v npm >/dev/null; then
  (cd "$work" && npm init -y >/dev/null && npm install --silent playwright-core@1 >/dev/null)
  cp scripts/web-save-check.mjs "$work/"
  node "$work/web-save-check.mjs" "http://127.0.0.1:$port/index.html" "$work"
  "$sg" render "$work/supergrain-state.json" -o "$work/from-web.png"
  echo "the web page's saved state renders natively"
fi

# The browser's speed on the mixed preset: its console lines over 45 s (page start included).
timeout 45 "${chrome[@]}" --enable-logging=stderr --v=0 \
  "http://127.0.0.1:$port/index.html?speed=50&log-fps" 2> "$work/web.txt" || true
web_mixed=$(grep -o 'fps [0-9.]* steps/s [0-9.]* step [0-9]* grains [0-9]* t [0-9.]*' "$work/web.txt" | tail -n 1 || true)
rate() { awk '{ for (i = 1; i < NF; i++) { if ($i == "step") s = $(i + 1); if ($i == "t") t = $(i + 1) } } END { if (t > 0) printf "%.1f", s / t }' <<< "$1"; }

{
  echo "supergrain view under Xvfb (software OpenGL), 1280x800, $(nproc) cores, $(date -u +%F)"
  echo
  echo "1,000-grain pour (examples/scenes/pour-1000.toml), once a second over 60 s:"
  cat "$work/fps.txt"
  # Real time: the scene's step is h = 0.01 s (the default), so 100 steps a second keep up.
  field() { awk -v k="$1" '{ for (i = 1; i < NF; i++) if ($i == k) print $(i + 1) }' "$work/fps.txt" | sort -g; }
  median() { awk '{ a[NR] = $1 } END { print a[int((NR + 1) / 2)] }'; }
  echo "frames per second: median $(field fps | median), lowest $(field fps | head -n 1)"
  echo "steps per second after the first second: median $(field steps/s | tail -n +2 | median), lowest $(field steps/s | sed -n 2p)"
  echo "simulated time $(tail -n 1 "$work/fps.txt" | awk '{ for (i = 1; i < NF; i++) { if ($i == "step") s = $(i + 1); if ($i == "t") t = $(i + 1) } } END { printf "%.1f s in %.1f s", s * 0.01, t }') of the clock (h = 0.01 s a step)"
  echo
  echo "mixed preset, 50 steps per frame, native, last line (t: seconds since start):"
  echo "$native_mixed"
  echo "mixed preset, 50 steps per frame, headless Chromium (SwiftShader WebGL), last line:"
  echo "$web_mixed"
  echo "steps per second since start: native $(rate "$native_mixed"), browser $(rate "$web_mixed")"
} | tee "$out/bench/viewer.txt"
