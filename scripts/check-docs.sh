#!/usr/bin/env bash
# Checks that docs/*.md state the present: no "old main", "issue N" /
# "issue #N" or "this branch", and at most one distinct commit hash per page
# (7-40 hex characters with at least one letter a-f and one digit, outside
# URLs). Names the file and line of every finding and exits non-zero; prints
# one line when every page passes.
set -euo pipefail
root="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
cd "$root"

history_words='old main|issue #?[0-9]+|this branch'
hash_pattern='\b[0-9a-f]{7,40}\b'

# The commit-like words of each line of $1 as "LINE HASH", URLs left out.
commit_hashes() {
  sed -E 's#[a-z]+://[^ )>]*##g' "$1" | grep -noE "$hash_pattern" | grep -E ':.*[a-f]' | grep -E ':.*[0-9]' |
    sed -E 's/^([0-9]+):/\1 /' || true
}

failed=0
pages=0
for page in docs/*.md; do
  pages=$((pages + 1))
  while IFS= read -r hit; do
    echo "$page:${hit%%:*}: history wording: ${hit#*:}" >&2
    failed=1
  done < <(grep -niE "$history_words" "$page" || true)

  hashes="$(commit_hashes "$page")"
  distinct="$(printf '%s\n' "$hashes" | awk 'NF { print $2 }' | sort -u | wc -l)"
  if [ "$distinct" -gt 1 ]; then
    while read -r line hash; do
      echo "$page:$line: commit $hash (the page cites $distinct commits, at most one allowed)" >&2
    done <<<"$hashes"
    failed=1
  fi
done

if [ "$failed" -ne 0 ]; then
  echo "check-docs: docs/ must state the present (see the lines above)" >&2
  exit 1
fi
echo "check-docs: OK ($pages pages, no history wording, at most one commit each)"
