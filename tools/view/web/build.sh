#!/usr/bin/env bash
# Rebuilds dist/ (committed; semap embeds it) from src/ and the three.js of package-lock.json:
#   tools/view/web/build.sh   (needs node and npm; installs the locked packages into node_modules/)
set -euo pipefail
cd "$(dirname "$0")"
npm ci --no-audit --no-fund --ignore-scripts  # esbuild's binary comes as @esbuild/linux-x64
npm run build
ls -l dist
