#!/usr/bin/env bash
# Builds the viewer for the browser into web/ (web/pkg holds the generated files) and, with
# --serve, serves it on http://localhost:8080 (or $PORT).
#
# Needs: the wasm32 target and wasm-bindgen-cli at the version in Cargo.lock; both are
# installed here on first use (from the Rust toolchain's and crates.io's servers).
set -euo pipefail
cd "$(dirname "$0")/.."

version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/[^0-9.]/, ""); print; exit }' Cargo.lock)
if ! rustup target list --installed | grep -qx wasm32-unknown-unknown; then
  echo "installing the wasm32-unknown-unknown target" >&2
  rustup target add wasm32-unknown-unknown
fi
if [ "$(wasm-bindgen --version 2>/dev/null | awk '{ print $2 }')" != "$version" ]; then
  echo "installing wasm-bindgen-cli $version (a few minutes, once)" >&2
  cargo install wasm-bindgen-cli --version "$version"
fi

# Without debug info the page loads a third of the bytes.
CARGO_PROFILE_RELEASE_DEBUG=0 cargo build --release --target wasm32-unknown-unknown -p supergrain-viewer
target=$(cargo metadata --format-version 1 --no-deps |
  python3 -c 'import json, sys; print(json.load(sys.stdin)["target_directory"])')
# Bound into a fresh folder, then moved into place: a failure leaves the last page as it was.
fresh=$(mktemp -d web/.pkg.XXXXXX)
trap 'rm -rf "$fresh"' EXIT
wasm-bindgen --target web --no-typescript --out-dir "$fresh" \
  "$target/wasm32-unknown-unknown/release/supergrain_viewer.wasm"
rm -rf web/pkg
mv "$fresh" web/pkg
echo "built web/ ($(du -sh web/pkg | cut -f1) in web/pkg)" >&2

if [ "${1:-}" = "--serve" ]; then
  port=${PORT:-8080}
  echo "serving on http://localhost:$port (Ctrl-C stops)" >&2
  exec python3 -m http.server "$port" --directory web --bind 127.0.0.1
fi
