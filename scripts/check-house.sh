#!/usr/bin/env bash
# The house rules that neither rustc nor clippy keeps, checked in CI (.ci/run). Each failing rule
# prints its offenders; the exit status is non-zero when any rule fails.
#   - no Rust source file over 600 lines (src, tests and benches alike);
#   - no two types of the workspace with the same name (public or not);
#   - comments carry no history: no "issue N" references (those go to commit messages and docs/);
#   - each crate depends only on the crates below it (interface <- core <- vulkan <- app);
#   - `cargo doc --no-deps` with broken intra-doc links denied ([workspace.lints.rustdoc]);
#   - README.md within 8,000 characters (what grows goes to docs/).
# Clippy keeps the others: too_many_lines at 100 ([workspace.lints.clippy], clippy.toml).
set -uo pipefail
cd "$(dirname "$0")/.."
failed=0
fail() { echo "house: $*"; failed=1; }

max_lines=600
long=$(git ls-files --cached --others --exclude-standard 'crates/*.rs' | xargs wc -l | grep -v ' total$' | awk -v m=$max_lines '$1 > m' | sort -rn)
if [ -n "$long" ]; then
  fail "Rust files over $max_lines lines (split each by concept):"
  printf '%s\n' "$long" | sed 's/^/    /'
fi

# Every struct, enum, trait and type alias in the crates' sources (test modules' files aside),
# whatever its visibility: a private type that shares a public one's name is a second concept
# under one name all the same. A trait's associated types (declared in the trait, defined in each
# impl) are one concept each, not types of their own: `type` counts at the top level only.
dups=$(git ls-files --cached --others --exclude-standard 'crates/*/src/*.rs' 'crates/*/src/**/*.rs' | grep -v '/tests\.rs$\|/tests/' |
  xargs grep -HoE '^(\s*(pub(\([a-z]+\))? )?(struct|enum|trait)|(pub(\([a-z]+\))? )?type) [A-Z][A-Za-z0-9_]*' |
  sed -E 's/:\s*(pub(\([a-z]+\))? )?(struct|enum|trait|type) /\t/' | sort -t$'\t' -k2,2 |
  awk -F'\t' '{ n[$2]++; where[$2] = where[$2] "    " $1 "\n" } END { for (t in n) if (n[t] > 1) printf "  %s:\n%s", t, where[t] }')
if [ -n "$dups" ]; then
  fail "types with the same name (one name per concept):"
  printf '%s\n' "$dups"
fi

history=$(git ls-files --cached --others --exclude-standard 'crates/*.rs' 'crates/*.glsl' 'crates/*.comp' 'crates/*.vert' 'crates/*.frag' |
  xargs grep -nE '//.*\b[Ii]ssues? [0-9]+' || true)
if [ -n "$history" ]; then
  fail "comments that narrate history (issue numbers belong in commit messages):"
  printf '%s\n' "$history" | sed 's/^/    /'
fi

# The layers: a crate's manifest names only the crates below it.
deps_of() { sed -n '/^\[dependencies\]/,/^\[/p' "crates/$1/Cargo.toml" | grep -oE '^lensray[a-z-]*' | sort -u | tr '\n' ' '; }
[ -z "$(deps_of lensray-interface)" ] || fail "lensray-interface depends on $(deps_of lensray-interface)(it depends on no other lensray crate)"
[ "$(deps_of lensray-core)" = "lensray-interface " ] || fail "lensray-core depends on $(deps_of lensray-core)(only lensray-interface)"
[ "$(deps_of lensray-vulkan)" = "lensray-core " ] || fail "lensray-vulkan depends on $(deps_of lensray-vulkan)(only lensray-core)"
if grep -rqE '^\s*unsafe |unsafe \{|#!?\[allow\(unsafe_code' crates/lensray-interface/src crates/lensray-core/src crates/lensray/src; then
  fail "unsafe code outside lensray-vulkan:"
  grep -rnE '^\s*unsafe |unsafe \{|#!?\[allow\(unsafe_code' crates/lensray-interface/src crates/lensray-core/src crates/lensray/src | sed 's/^/    /'
fi
# Inside lensray-vulkan, unsafe blocks live in core/, the layer that owns every Vulkan object.
outside_core=$(grep -rnE 'unsafe \{|unsafe fn |unsafe impl ' crates/lensray-vulkan/src --include=*.rs | grep -v '^crates/lensray-vulkan/src/core/' || true)
[ -z "$outside_core" ] || fail "unsafe code in lensray-vulkan outside src/core/:
$(printf '%s\n' "$outside_core" | sed 's/^/    /')"

max_readme=8000
readme=$(wc -m <README.md)
echo "house: README.md is $readme characters (at most $max_readme)"
[ "$readme" -le $max_readme ] || fail "README.md is $readme characters, over $max_readme: move what grew to docs/"

if ! doc_log=$(cargo doc --workspace --no-deps --quiet 2>&1); then
  fail "cargo doc --no-deps failed (broken intra-doc links are denied):"
  printf '%s\n' "$doc_log" | grep -E '^(error|warning)|-->' | sed 's/^/    /'
fi

[ $failed -eq 0 ] && echo "house: ok (files <= $max_lines lines, unique type names, no history in comments, layers, docs, README)"
exit $failed
