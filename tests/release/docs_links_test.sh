#!/usr/bin/env bash
# Every relative link of the README, CHANGELOG, docs/ (its subfolders too: design/, notebook/) and
# examples/ names a file that exists (sections move between documents; a link left behind is
# found here, not by a reader).
# Usage: docs_links_test.sh SOURCE_DIR
set -u
shopt -s globstar  # docs/**/*.md: docs/*.md and every subfolder's
root=$1
failures=0
for doc in "$root"/README.md "$root"/CHANGELOG.md "$root"/docs/**/*.md "$root"/examples/*.md; do
  [[ -f $doc ]] || continue
  folder=$(dirname "$doc")
  # [text](target) and ![alt](target), the target up to a space, ')' or '#'.
  while IFS= read -r target; do
    [[ -z $target || $target == http://* || $target == https://* || $target == mailto:* ]] &&
      continue
    if [[ ! -e $folder/$target ]]; then
      echo "FAIL: ${doc#"$root"/} links to $target, which does not exist"
      failures=$((failures + 1))
    fi
  done < <(grep -o '\]([^) #]*' "$doc" | sed 's/^](//')
done
((failures == 0)) && echo "PASS: every relative link resolves"
exit $((failures > 0))
