#!/usr/bin/env bash
# Checks the built book (book/book) as a reader would get it: every local link resolves, no
# directive or raw LaTeX is left, math was rendered by KaTeX at build time with no CDN, and the
# computed values are there.
set -euo pipefail
cd "$(dirname "$0")/book"
fail=0
say() { echo "book check: $*" >&2; fail=1; }
pages=$(ls *.html)
for page in $pages; do
  # local links (href/src without a scheme), fragment stripped
  grep -o 'href="[^"#]*\|src="[^"#]*' "$page" | sed 's/^[a-z]*="//' | grep -v '^[a-z]*:' | grep -v '^$' | sort -u |
  while read -r target; do
    [ -e "$target" ] || echo "$page -> $target"
  done > /tmp/owb-missing-$$ || true
  if [ -s /tmp/owb-missing-$$ ]; then say "broken links: $(tr '\n' ' ' < /tmp/owb-missing-$$)"; fi
  rm -f /tmp/owb-missing-$$
  if grep -q '{{#owb' "$page"; then say "$page: unexpanded directive"; fi
  if grep -q '\\begin{aligned}' "$page" && ! grep -q 'class="katex' "$page"; then say "$page: raw LaTeX, not rendered"; fi
  if grep -qi 'cdn.jsdelivr\|cdnjs\|unpkg.com' "$page"; then say "$page: links a CDN"; fi
done
# math is rendered and its stylesheet and fonts are shipped
grep -q 'class="katex' gains.html || say "gains.html: no rendered math"
ls katex/katex*.css >/dev/null 2>&1 || say "KaTeX stylesheet missing"
ls katex/fonts/KaTeX_Main-Regular.woff2 >/dev/null 2>&1 || say "KaTeX fonts missing"
# computed values, as the workbench prints them
grep -q 'L = \[-6; -12\]' gains.html || say "gains.html: Stoustrup's gain missing"
grep -q '<svg' polynomials.html || say "polynomials.html: figure missing"
grep -q '286\.6' kalman.html || say "kalman.html: Kalman bandwidth missing"
grep -q 'erratum' errata.html || say "errata.html: errata missing"
# the workbench for the browser is shipped with the book, and every exercise has answer fields
for f in owb-web/owb_web.js owb-web/owb_web_wasm.js katex/katex.min.js; do
  [ -s "$f" ] || say "$f missing (web/build.sh, install-katex.sh)"
done
for page in $(grep -l 'Exercise: ' $pages); do
  grep -q 'class="owb-exercise"' "$page" || say "$page: an exercise without answer fields"
done
grep -q 'class="owb-playground"' workbench.html || say "workbench.html: no playground"
[ "$fail" = 0 ] && echo "book check: $(echo "$pages" | wc -w) pages, links resolve, math rendered offline, computed values present"
exit "$fail"
