#!/usr/bin/env bash
# Replaces the vendored three.js with the npm package `three` at the given version.
# Usage: hamel-scene/src/three/update.sh 0.185.1
set -euo pipefail
version="${1:?usage: update.sh <three version>}"
here="$(cd "$(dirname "$0")" && pwd)"
work="$(mktemp -d)"
trap 'rm -rf "$work"' EXIT
(cd "$work" && npm pack "three@$version" >/dev/null && tar xzf "three-$version.tgz")
package="$work/package"
cp "$package/build/three.core.min.js" "$package/build/three.module.min.js" \
    "$package/examples/jsm/controls/OrbitControls.js" "$package/LICENSE" "$here/"
echo "copied three $version into $here; update README.md there (version, integrity)"
