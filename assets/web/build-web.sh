#!/usr/bin/env bash
# Builds raylab's web page into a folder: index.html, raylab.js and raylab_bg.wasm, ready for any
# static file server (`python3 -m http.server -d target/site`).
#
#   assets/web/build-web.sh [OUT_DIR]        (default: target/site)
#
# It needs the wasm32-unknown-unknown target and wasm-bindgen-cli at exactly the version of the
# wasm-bindgen crate in Cargo.lock; it adds either when missing. wasm-opt (Debian's binaryen) shrinks
# the .wasm further when it is installed. The build has its own target folder (target/web, or
# $CARGO_TARGET_DIR) so it never waits on, or invalidates, the desktop build.
set -euo pipefail
cd "$(dirname "$0")/../.."
out="${1:-target/site}"
target_dir="${CARGO_TARGET_DIR:-target/web}"

if [ ! -d "$(rustc --print sysroot)/lib/rustlib/wasm32-unknown-unknown/lib" ]; then
  echo "== rustup target add wasm32-unknown-unknown"
  rustup target add wasm32-unknown-unknown
fi

# wasm-bindgen's generated JavaScript must come from the same version as the crate.
version=$(awk '/^name = "wasm-bindgen"$/ { getline; gsub(/version = |"/, ""); print; exit }' Cargo.lock)
if [ "$(wasm-bindgen --version 2>/dev/null | awk '{ print $2 }')" != "$version" ]; then
  echo "== cargo install wasm-bindgen-cli --version $version"
  # --locked builds it with the dependencies it was released with; where the registry no longer
  # serves one of those, the newest compatible ones do.
  cargo install --locked wasm-bindgen-cli --version "$version" ||
    cargo install wasm-bindgen-cli --version "$version"
fi

echo "== cargo build --target wasm32-unknown-unknown --profile web"
CARGO_TARGET_DIR="$target_dir" cargo build --bin raylab --target wasm32-unknown-unknown --profile web
wasm="$target_dir/wasm32-unknown-unknown/web/raylab.wasm"

# wasm-opt (Debian's binaryen 108) shrinks the .wasm by about a fifth (less once gzipped). It runs before wasm-bindgen: run
# after it, that old wasm-opt breaks the table of JavaScript references wasm-bindgen adds.
if command -v wasm-opt >/dev/null 2>&1; then
  echo "== wasm-opt -Os"
  # The features rustc enables for wasm32 by default; wasm-opt must be told it may keep them.
  if wasm-opt -Os --enable-bulk-memory --enable-mutable-globals --enable-nontrapping-float-to-int \
      --enable-sign-ext --enable-reference-types --enable-multivalue "$wasm" -o "$wasm.opt"; then
    wasm="$wasm.opt"
  else
    echo "wasm-opt failed: the .wasm is used as rustc wrote it"
  fi
else
  echo "wasm-opt not found (apt-get install binaryen): the .wasm is used as rustc wrote it"
fi

rm -rf "$out"
mkdir -p "$out"
wasm-bindgen --target web --no-typescript --out-dir "$out" --out-name raylab "$wasm"
cp assets/web/index.html "$out/"
raw=$(wc -c <"$out/raylab_bg.wasm")
gzipped=$(gzip -9 -c "$out/raylab_bg.wasm" | wc -c)
echo "== built $out: raylab_bg.wasm is $((raw / 1024)) KiB, $((gzipped / 1024)) KiB gzipped"
