#!/usr/bin/env bash
# The documents agree with each other and stand alone:
# - every figure the README quotes, marked `VALUE<!-- figure: NAME -->`, is marked with the same
#   NAME and the same VALUE in docs/BENCHMARKS.md's headline table, where each NAME is marked once,
#   and BENCHMARKS gives that VALUE again in the section it comes from;
# - every relative link of every Markdown file ([text](path), ![alt](path), with an optional
#   #anchor) names a file of the repository, and the anchor a heading of that file (GitHub's
#   slugs, for ASCII headings);
# - every file NAME.md named anywhere in the documents, the man pages or the sources is in the
#   repository (a document it cites must be one it contains).
# usage: check-docs.sh [SOURCE_DIR]
set -u
src=${1:-$(cd "$(dirname "$0")/.." && pwd)}
export LC_ALL=C
errors=0
checks=0

fail() {
	echo "check-docs: $*" >&2
	errors=$((errors + 1))
}

# The tracked-looking files of the tree: no build directories, no .git.
files() {
	find "$src" \( -name '.git' -o -name 'build*' -o -name 'fuzz-out' -o -name 'subprojects' \) \
		-prune -o -type f \( "$@" \) -print
}

# figures FILE: NAME<TAB>VALUE for each marked figure of FILE.
figures() {
	grep -oE '[0-9][0-9.,–×]*<!-- figure: [a-z0-9-]+ -->' "$1" |
		sed -E 's/^(.*)<!-- figure: ([a-z0-9-]+) -->$/\2\t\1/'
}

readme=$src/README.md
bench=$src/docs/BENCHMARKS.md
figures "$readme" >"${TMPDIR:-/tmp}/check-docs.$$.readme"
figures "$bench" >"${TMPDIR:-/tmp}/check-docs.$$.bench"
trap 'rm -f "${TMPDIR:-/tmp}/check-docs.$$."*' EXIT
[ -s "${TMPDIR:-/tmp}/check-docs.$$.readme" ] || fail "README.md marks no figure"
dups=$(cut -f1 "${TMPDIR:-/tmp}/check-docs.$$.bench" | sort | uniq -d)
[ -z "$dups" ] || fail "BENCHMARKS.md marks these figures more than once: $dups"
while IFS=$'\t' read -r name value; do
	want=$(awk -F'\t' -v n="$name" '$1 == n { print $2 }' "${TMPDIR:-/tmp}/check-docs.$$.bench")
	if [ -z "$want" ]; then
		fail "README.md quotes figure '$name' ($value), which BENCHMARKS.md does not mark"
	elif [ "$want" != "$value" ]; then
		fail "figure '$name': README.md says $value, BENCHMARKS.md $want"
	fi
	checks=$((checks + 1))
done <"${TMPDIR:-/tmp}/check-docs.$$.readme"
while IFS=$'\t' read -r name value; do
	n=$(sed 's/<!-- figure: [a-z0-9-]* -->//g' "$bench" | grep -oF -- "$value" | wc -l)
	[ "$n" -ge 2 ] || fail "figure '$name' ($value) is in BENCHMARKS.md's headline table only," \
		"not in the section it comes from"
	checks=$((checks + 1))
done <"${TMPDIR:-/tmp}/check-docs.$$.bench"

# slugs FILE: the anchors of FILE's headings, outside fenced blocks, as GitHub makes them.
slugs() {
	awk '/^```/ { fence = !fence; next } !fence && /^#+ / { sub(/^#+ +/, ""); print }' "$1" |
		tr 'A-Z' 'a-z' | sed -E 's/[^a-z0-9 _-]//g; s/ /-/g'
}

while IFS= read -r md; do
	dir=$(dirname "$md")
	rel=${md#"$src"/}
	# Links outside fenced blocks and inline code.
	awk '/^```/ { fence = !fence; next } !fence { gsub(/`[^`]*`/, ""); print }' "$md" |
		grep -oE '\]\([^) ]+\)' | sed -E 's/^\]\((.*)\)$/\1/' | sort -u |
		while IFS= read -r link; do
			case $link in
			http:* | https:* | mailto:*) continue ;;
			esac
			path=${link%%#*}
			anchor=
			[ "$path" = "$link" ] || anchor=${link#*#}
			if [ -z "$path" ]; then
				target=$md
			else
				target=$dir/$path
			fi
			if [ ! -e "$target" ]; then
				echo "check-docs: $rel links to $link: no such file" >&2
				echo x
				continue
			fi
			if [ -n "$anchor" ] && [[ $target == *.md ]] && ! slugs "$target" | grep -qxF -- "$anchor"; then
				echo "check-docs: $rel links to $link: no such heading" >&2
				echo x
			fi
		done >"${TMPDIR:-/tmp}/check-docs.$$.links"
	bad=$(wc -l <"${TMPDIR:-/tmp}/check-docs.$$.links")
	errors=$((errors + bad))
	checks=$((checks + 1))
done < <(files -name '*.md')

# Every Markdown file named is a file of the repository.
known=$(files -name '*.md' | xargs -n1 basename | sort -u)
while IFS= read -r f; do
	[ "$f" != "$src/tests/check-docs.sh" ] || continue
	for name in $(grep -oE '[A-Za-z0-9_-]+\.md\b' "$f" | sort -u); do
		grep -qxF -- "$name" <<<"$known" || fail "${f#"$src"/} names $name, which is not in the repository"
		checks=$((checks + 1))
	done
done < <(files -name '*.md' -o -name '*.scd' -o -name '*.c' -o -name '*.h' -o -name '*.sh' \
	-o -name 'meson.build')

if [ "$errors" -ne 0 ]; then
	echo "check-docs: $errors problems" >&2
	exit 1
fi
echo "check-docs: $checks checks passed"
