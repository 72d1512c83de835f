#!/usr/bin/env bash
# Regenerate docs/fmu.md's FMU variable table (between the variables:begin/end markers) from
# the one variable table: cargo run --bin relnav-fmu -- --variables-markdown.
set -euo pipefail
cd "$(dirname "${BASH_SOURCE[0]}")/.."
table="$(cargo run -q --bin relnav-fmu -- --variables-markdown)"
python3 - "$table" <<'PY'
import re, sys
table = sys.argv[1].rstrip("\n") + "\n"
s = open("docs/fmu.md").read()
begin = s.index("<!-- variables:begin")
begin = s.index("\n", begin) + 1
end = s.index("<!-- variables:end -->")
open("docs/fmu.md", "w").write(s[:begin] + table + s[end:])
PY
