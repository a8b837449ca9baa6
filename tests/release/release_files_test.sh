#!/usr/bin/env bash
# The files a packager or a citing author reads name this version and the licence: LICENSE is
# BSD-3-Clause, CITATION.cff gives the project() version and that licence, CHANGELOG.md has a
# section for the version (or Unreleased above it), and the program says the same version.
# Usage: release_files_test.sh SOURCE_DIR VERSION RADIOSITY
set -u
root=$1 version=$2 radiosity=$3
failures=0
fail() { echo "FAIL: $*"; failures=$((failures + 1)); }

grep -q "^BSD 3-Clause License" "$root/LICENSE" || fail "LICENSE is not the BSD 3-Clause text"
grep -qx "version: \"$version\"" "$root/CITATION.cff" ||
  fail "CITATION.cff does not give version \"$version\""
grep -qx "license: BSD-3-Clause" "$root/CITATION.cff" || fail "CITATION.cff gives another licence"
grep -qx "cff-version: 1.2.0" "$root/CITATION.cff" || fail "CITATION.cff is not CFF 1.2.0"
grep -qx "## $version" "$root/CHANGELOG.md" || fail "CHANGELOG.md has no section ## $version"
"$radiosity" --version | grep -q "radiosity $version" || fail "radiosity --version is not $version"

((failures == 0)) && echo "release files name $version"
exit $((failures > 0))
