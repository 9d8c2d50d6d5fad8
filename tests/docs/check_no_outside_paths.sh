#!/usr/bin/env bash
# Fails if a tracked file refers to the team's folder beside the repository ("../shared"):
# everything a user needs must be inside the repository (docs/, issue 36). This script is
# the only file allowed to name the pattern. Run: bash tests/docs/check_no_outside_paths.sh
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/../.."
self="tests/docs/check_no_outside_paths.sh"
pattern='\.\./shared'
if git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  hits=$(git grep -n -I -E "$pattern" -- . ":(exclude)$self" || true)
else  # a tarball without .git: every file
  hits=$(grep -r -n -I -E "$pattern" --exclude-dir=build --exclude-dir=.git . | grep -v "^\./$self:" || true)
fi
if [ -n "$hits" ]; then
  echo "files refer to a path outside the repository (../shared); point to docs/ instead:"
  echo "$hits"
  exit 1
fi
echo "no tracked file refers to ../shared"
