#!/usr/bin/env bash
# Refresh the vendored three.js bundle of the replay viewer from npm (pinned in package.json and
# package-lock.json; change the version there, then run this). Writes
# templates/assets/replay/three.min.js (a classic script defining window.SITEGEN_THREE, see
# entry.js) and three.js' license beside it. Not part of a build: the output is committed.
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund --ignore-scripts >/dev/null
out=../../templates/assets/replay
mkdir -p "$out"
version=$(node -p "JSON.parse(require('fs').readFileSync('node_modules/three/package.json')).version")
node node_modules/esbuild/bin/esbuild entry.js --bundle --format=iife --global-name=SITEGEN_THREE \
  --minify --legal-comments=none --target=es2020 --log-level=warning \
  --banner:js="/* three.js ${version} (MIT, see LICENSE-three.txt): GLTFLoader, OrbitControls and the core classes they use; bundled by tools/replay-viewer/refresh.sh */" \
  --outfile="$out/three.min.js"
cp node_modules/three/LICENSE "$out/LICENSE-three.txt"
ls -l "$out/three.min.js" "$out/LICENSE-three.txt"
