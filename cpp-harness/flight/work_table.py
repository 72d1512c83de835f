"""The table of cpp-harness/flight/work.c's callgrind dumps: per filter and orbit, the
median instruction count of the nominal steps and each kind's worst step, as a multiple of
that median. Usage: work_table.py DIR [LIMIT]: exits 1 if a nominal step (the same length
and sensor set as the others) exceeds LIMIT times their median (no limit: report only);
the other kinds do more work by design (more updates, a new discrete model) and are
reported."""
import pathlib
import re
import statistics
import sys

counts = {}
for f in pathlib.Path(sys.argv[1]).glob("cg.out.*"):
    text = f.read_text()
    label = re.search(r"^desc: Trigger: Client Request: (.*)$", text, re.M)
    total = re.search(r"^summary: (\d+)$", text, re.M)
    if label and total:
        counts.setdefault(label.group(1), []).append(int(total.group(1)))
limit = float(sys.argv[2]) if len(sys.argv) > 2 else None
runs = sorted({tuple(k.split("/")[:2]) for k in counts})
kinds = [k for k in dict.fromkeys(lab.split("/")[2] for lab in counts) if k != "nominal"]
print("| filter | orbit | nominal median | nominal worst | " + " | ".join(kinds) + " | worst / median |")
print("|---|---|---:|---:|" + "---:|" * len(kinds) + "---:|")
bad = 0
for filt, orbit in runs:
    nominal = counts[f"{filt}/{orbit}/nominal"]
    med = statistics.median(nominal)
    worst = {k: max(counts[f"{filt}/{orbit}/{k}"]) for k in kinds}
    ratio = max(max(worst.values()), max(nominal)) / med
    cells = " | ".join(f"{worst[k] / med:.2f}" for k in kinds)
    print(f"| {filt} | {orbit} | {med:,.0f} | {max(nominal) / med:.2f} | {cells} | {ratio:.2f} |")
    if limit is not None and max(nominal) / med > limit:
        print(f"work_table: {filt}/{orbit}: a nominal step {max(nominal) / med:.2f} times the median")
        bad += 1
sys.exit(1 if bad else 0)
