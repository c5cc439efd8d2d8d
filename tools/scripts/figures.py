#!/usr/bin/env python3
"""One source for every figure: checks (or, with --fix, rewrites) every size, instruction count,
stack depth and host speed quoted in README.md, docs/*.md and the headers' comments against the
measurements the test command made.

  figures.py --source DIR --build DIR [--fix | --self-test]

Sources (keys of tests/footprint/figures.json):
  meter:<operation>[@<core>-<opt>]:ins|stack   <build>/footprint/meter.json (the meter),
                                               Cortex-M4 -Os unless named
  size:<probe>[@<target>]:text|rodata          <build>/tests/footprint/footprint-report.txt
                                               (the footprint probes), Cortex-M4 unless named
  static:<object>                              <build>/tests/footprint/statics/statics.txt
                                               (sizeof of a firmware's static objects, nm)
  target:<operation>:ins|stack                 tests/meter/budgets.json, its "targets"
  <key>|<key>...                               the largest of them (a worst case)
  bench:<column>:<operation>                   bench/RESULTS.md, its summary table: the
                                               committed record of a benchmark run and its
                                               machine (host speeds are not measured by the
                                               test command: a shared machine's timings are
                                               noise)

Every figure (a number followed by B, KB, bytes, -byte, instructions, "a byte", "a frame", ns
or x, or the first of "N / M B") in the Markdown files, every number of the headers' firmware
contract blocks, and every instruction or stack figure in other header comments, must be
covered by an
entry of figures.json: "at" is the text around it, with {} for each figure, which "keys" name
in order; or an entry with "fixed" (a constant of a specification or of the design, the reason
given) or "history" (a figure of a past measurement, kept as such). Blocks between
<!-- figures:NAME --> and <!-- /figures --> are generated (meter-table, size-table) or history
(history: not checked). A figure no entry covers, an entry whose text is gone, and a figure
that differs from its source all fail, with the file, the line, the figure and the measured
value. --fix rewrites keyed figures and generated blocks in place from the measurements.
"""

import argparse
import json
import os
import re
import sys

NUM = r"(\d+(?:\.\d+)?)"
# A figure: a number followed by a unit of size, count or time.
FIGURE = re.compile(
    r"(?<![\w.\-/×#])(?<!\.\.)(\d+(?:\.\d+)?)(?:\*\*)?"
    r"(?:\s+(?:K?B)\b|\s+bytes?\b|-byte\b|\s+(?:Cortex-M4\s+)?instructions?\b|-instruction\b"
    r"|\s+a\s+byte\b|\s+a\s+frame\b|\s*ns\b|×|\*?\*?\s+/\s+\d+\s+B\b)")
# Outside the contract blocks, a header comment's measured figures only: instructions, stack.
MEASURED = re.compile(
    r"(?<![\w.\-/×#])(\d+(?:\.\d+)?)(?:\s+(?:Cortex-M4\s+)?instructions?\b|-instruction\b"
    r"|\s+(?:B|bytes)\s+of\s+stack\b)")
# Inside a firmware contract block, every number is a figure (a count without its unit, "96 at
# its last byte", is one too), but those in words, hex, versions and ranges of bits ("64-bit").
CONTRACT = re.compile(FIGURE.pattern + r"|(?<![\w.\-/×#+])(\d+(?:\.\d+)?)(?![\w\-])")
BLOCK = re.compile(r"<!-- figures:([\w-]+) -->\n(.*?)<!-- /figures -->", re.S)
CORES = ("cortex-m0plus", "cortex-m4", "rv32imc")
OPTS = ("Os", "O2")


class Missing(Exception):
    pass


class Sources:
    def __init__(self, source, build):
        self.errors = []
        self.meter = {}
        path = os.path.join(build, "footprint", "meter.json")
        for r in self._json(path, []):
            self.meter[(r["operation"], r["core"], r["opt"])] = r
        self.meter_rows = self._json(path, [])
        self.sizes = {}
        path = os.path.join(build, "tests", "footprint", "footprint-report.txt")
        for line in self._lines(path):
            m = re.match(r"(\w+)-([\w-]+): \.text (\d+) B .*?\.rodata (\d+) B .*?\.data (\d+) B,"
                         r" \.bss (\d+) B", line)
            if m:  # the last line of a probe wins (the report is appended to by each run)
                self.sizes[(m.group(1), m.group(2))] = dict(
                    text=int(m.group(3)), rodata=int(m.group(4)),
                    data=int(m.group(5)), bss=int(m.group(6)))
        self.statics = {}
        for line in self._lines(os.path.join(build, "tests", "footprint", "statics",
                                             "statics.txt")):
            name, size = line.split()[:2]
            self.statics[name] = int(size)
        budgets = self._json(os.path.join(source, "tests", "meter", "budgets.json"), {})
        self.targets = {t["operation"]: t for t in budgets.get("targets", [])}
        self.bench = {}
        path = os.path.join(source, "bench", "RESULTS.md")
        text = open(path).read() if os.path.exists(path) else ""
        summary = text.split("## Summary", 1)[-1].split("\n## ", 1)[0]
        header = None
        for line in summary.splitlines():
            cells = [c.strip() for c in line.strip().strip("|").split("|")]
            if len(cells) < 4 or set(cells[0]) <= set("-:"):
                continue
            if header is None or cells[0] in ("protocol", "operation"):
                header = cells
                continue
            op = " ".join(cells[:2]) if header[0] == "protocol" else cells[0]
            self.bench[op] = dict(zip(header, cells))

    def _json(self, path, default):
        if not os.path.exists(path):
            self.errors.append(f"no measurements: {path} (run the meter and footprint tests)")
            return default
        with open(path) as f:
            return json.load(f)

    def _lines(self, path):
        if not os.path.exists(path):
            self.errors.append(f"no measurements: {path} (run the footprint tests)")
            return []
        with open(path) as f:
            return [line.strip() for line in f if line.strip()]

    def value(self, key):
        if "|" in key:  # the worst of several measurements
            return max(self.value(k) for k in key.split("|"))
        kind, _, rest = key.partition(":")
        if kind == "meter":
            name, field = rest.rsplit(":", 1)
            op, _, where = name.partition("@")
            core, opt = where.rsplit("-", 1) if where else ("cortex-m4", "Os")
            row = self.meter.get((op, core, opt))
            if row is None:
                raise Missing(f"{key}: not measured")
            return row[{"ins": "instructions", "stack": "stack_bytes"}[field]]
        if kind == "size":
            name, field = rest.rsplit(":", 1)
            probe, _, target = name.partition("@")
            row = self.sizes.get((probe, target or "cortex-m4"))
            if row is None:
                raise Missing(f"{key}: not in the footprint report")
            return row[field]
        if kind == "static":
            if rest not in self.statics:
                raise Missing(f"{key}: not in statics.txt")
            return self.statics[rest]
        if kind == "target":
            op, field = rest.rsplit(":", 1)
            if op not in self.targets:
                raise Missing(f"{key}: no such target in budgets.json")
            return self.targets[op][{"ins": "instructions", "stack": "stack_bytes"}[field]]
        if kind == "bench":
            column, _, op = rest.partition(":")
            rows = [r for name, r in self.bench.items() if name.startswith(op)]
            if len(rows) != 1:
                raise Missing(f"{key}: {len(rows)} rows of bench/RESULTS.md's summary match")
            cell = rows[0].get(column, "")
            m = re.match(NUM, cell)
            if not m:
                raise Missing(f"{key}: no figure in the cell {cell!r}")
            return float(m.group(1))
        raise Missing(f"{key}: unknown source")


def shown(value, like):
    """`value` written with as many decimals as the figure `like` shows."""
    decimals = len(like.split(".")[1]) if "." in like else 0
    return f"{value:.{decimals}f}"


def describe(key):
    keys = key.split("|")
    return keys[0] if len(keys) == 1 else f"the worst of {keys[0]} and {len(keys) - 1} more"


def at_pattern(at):
    parts = [re.escape(p) for p in at.split("{}")]
    # a space of the entry matches any run of spaces, line breaks and comment slashes
    parts = [re.sub(r"(\\ )+", r"(?:\\s|//+)+", p) for p in parts]
    return re.compile(NUM.join(parts))


def comment_text(text):
    """The header's text with everything but comments blanked (offsets kept), and the spans of
    its firmware contract blocks."""
    out = []
    contracts = []
    offset = 0
    in_contract = None
    for line in text.splitlines(keepends=True):
        k = line.find("//")
        if k >= 0:
            out.append(" " * k + line[k:])
            if "Firmware contract" in line:
                in_contract = offset
        else:
            out.append(re.sub(r"[^\n]", " ", line))
            if in_contract is not None:
                contracts.append((in_contract, offset))
                in_contract = None
        offset += len(line)
    return "".join(out), contracts


def meter_table(src, spec):
    notes = spec.get("notes", {})
    ops = []
    for r in src.meter_rows:
        if r["operation"] not in ops:
            ops.append(r["operation"])
    lines = ["| operation | " + " | ".join(f"{c} -{o}" for c in CORES for o in OPTS) + " |",
             "|---|" + "---:|" * (len(CORES) * len(OPTS))]
    for op in ops:
        cells = []
        for c in CORES:
            for o in OPTS:
                r = src.meter.get((op, c, o))
                cells.append(f"{r['instructions']} / {r['stack_bytes']} B" if r else "—")
        note = f" ({notes[op]})" if op in notes else ""
        lines.append(f"| `{op}`{note} | " + " | ".join(cells) + " |")
    return "\n".join(lines) + "\n"


def size_table(src, spec):
    names = {"cortex-m0plus": "M0+", "cortex-m4": "M4", "rv32imc": "rv32imc"}
    lines = ["| probe | " + " | ".join(f"{names[c]} {s}" for c in CORES
                                        for s in (".text", ".rodata")) + " | .data + .bss |",
             "|---|" + "---:|" * 7]
    for label, probe in spec["rows"]:
        cells = []
        ram = 0
        for c in CORES:
            row = src.sizes.get((probe, c))
            if row is None:
                raise Missing(f"size-table: {probe} on {c} not in the footprint report")
            cells += [str(row["text"]), str(row["rodata"])]
            ram = max(ram, row["data"] + row["bss"])
        lines.append(f"| {label} | " + " | ".join(cells) + f" | {ram} |")
    return "\n".join(lines) + "\n"


GENERATORS = {"meter-table": meter_table, "size-table": size_table}


def line_of(text, offset):
    return text.count("\n", 0, offset) + 1


def check_file(path, rel, entries, blocks, src, fix, problems):
    text = open(path).read()
    edits = []  # (start, end, replacement)
    covered = []  # spans
    scan_spans = []  # (start, end, regex) where figures must be covered
    if rel.endswith(".md"):
        pos = 0
        for m in BLOCK.finditer(text):
            scan_spans.append((pos, m.start(), FIGURE))
            pos = m.end()
            name = m.group(1)
            if name == "history":
                continue
            if name not in GENERATORS:
                problems.append(f"{rel}:{line_of(text, m.start())}: unknown block {name}")
                continue
            try:
                want = GENERATORS[name](src, blocks.get(name, {}))
            except Missing as e:
                problems.append(f"{rel}:{line_of(text, m.start())}: {e}")
                continue
            if m.group(2) != want:
                if fix:
                    edits.append((m.start(2), m.end(2), want))
                else:
                    got = m.group(2).splitlines()
                    new = want.splitlines()
                    diff = next((i for i in range(max(len(got), len(new)))
                                 if i >= len(got) or i >= len(new) or got[i] != new[i]), 0)
                    problems.append(
                        f"{rel}:{line_of(text, m.start(2)) + diff}: the generated {name} differs "
                        f"from the measurements: {got[diff] if diff < len(got) else '(none)'!r}"
                        f", measured {new[diff] if diff < len(new) else '(none)'!r}")
        scan_spans.append((pos, len(text), FIGURE))
        scanned = text
    else:
        scanned, contracts = comment_text(text)
        pos = 0
        for start, end in contracts:
            scan_spans += [(pos, start, MEASURED), (start, end, CONTRACT)]
            pos = end
        scan_spans.append((pos, len(text), MEASURED))
    for e in entries:
        pattern = at_pattern(e["at"])
        matches = list(pattern.finditer(scanned))
        if not matches:
            problems.append(f"{rel}: a registered figure is gone (tests/footprint/figures.json): "
                            f"{e['at']!r}")
            continue
        keys = e.get("keys", [])
        if ("fixed" in e or "history" in e) == bool(keys) or len(keys) != pattern.groups:
            problems.append(f"{rel}: {e['at']!r}: needs one key a {{}} (or fixed/history "
                            f"without {{}})")
            continue
        for m in matches:
            if not keys:
                covered.append((m.start(), m.end()))
                continue
            for i, key in enumerate(keys, 1):
                covered.append((m.start(i), m.end(i)))
                try:
                    value = src.value(key)
                except Missing as err:
                    problems.append(f"{rel}:{line_of(text, m.start(i))}: {err}")
                    continue
                written = m.group(i)
                if float(shown(value, written)) != float(written):
                    if fix:
                        edits.append((m.start(i), m.end(i), shown(value, written)))
                    else:
                        context = re.sub(r"(?:\s|//+)+", " ", m.group(0)).strip()[:80]
                        problems.append(f"{rel}:{line_of(text, m.start(i))}: {written} in "
                                        f"{context!r}: measured "
                                        f"{shown(value, written)} ({describe(key)})")
    for start, end, regex in scan_spans:
        for m in regex.finditer(scanned, start, end):
            at = m.start(1) if m.group(1) is not None else m.start(2)
            if not any(a <= at < b for a, b in covered):
                figure = re.sub(r"\s+", " ", m.group(0).strip())
                problems.append(f"{rel}:{line_of(text, at)}: unregistered figure "
                                f"{figure!r} (register it in "
                                f"tests/footprint/figures.json with its source)")
    if fix and edits:
        for start, end, new in sorted(edits, reverse=True):
            text = text[:start] + new + text[end:]
        with open(path, "w") as f:
            f.write(text)
        print(f"figures: rewrote {len(edits)} figure(s) in {rel}")


def self_test(source, registry, src):
    """Plants a wrong figure at every keyed figure, one at a time, and an unregistered one in
    every file that has entries: each must be reported (the check cannot pass a stale figure)."""
    import shutil
    import tempfile
    missed = []
    planted = 0
    with tempfile.TemporaryDirectory() as tmp:
        for rel, entries in registry["files"].items():
            original = open(os.path.join(source, rel)).read()
            path = os.path.join(tmp, os.path.basename(rel))
            plants = []
            for e in entries:
                m = at_pattern(e["at"]).search(original)
                for i in range(1, len(e.get("keys", [])) + 1 if m else 1):
                    written = m.group(i)
                    wrong = str(int(float(written)) + 1) + (
                        "." + written.split(".")[1] if "." in written else "")
                    plants.append((m.start(i), m.end(i), wrong,
                                   f"{e['at']!r}, figure {i} = {wrong}"))
            # an unregistered figure: in a contract block for a header, in the text for docs
            at = original.find("Firmware contract")
            if rel.endswith(".hpp") and at >= 0:
                end = original.index("\n", at) + 1
                plants.append((end, end, "//   999 bytes of stack at worst.\n",
                               "an unregistered contract figure"))
            elif rel.endswith(".md"):
                plants.append((0, 0, "It takes 999 B.\n\n", "an unregistered figure"))
            problems = []
            check_file(os.path.join(source, rel), rel, entries, registry.get("blocks", {}), src,
                       False, problems)
            if problems:  # a plant must be what fails
                missed.append(f"{rel}: fails unplanted: {problems[0]}")
                continue
            for start, end, new, what in plants:
                with open(path, "w") as f:
                    f.write(original[:start] + new + original[end:])
                problems = []
                check_file(path, rel, entries, registry.get("blocks", {}), src, False, problems)
                planted += 1
                if not problems:
                    missed.append(f"{rel}: {what} passed")
            shutil.copy(os.path.join(source, rel), path)
    if missed:
        print("figures: the check missed:\n  " + "\n  ".join(missed), file=sys.stderr)
        return 1
    print(f"figures: each of {planted} planted figures (a wrong one at every registered "
          f"figure, an unregistered one in every file) fails the check")
    return 0


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    p.add_argument("--source", required=True, help="the source tree")
    p.add_argument("--build", required=True, help="the build tree the meter and probes ran in")
    p.add_argument("--registry", help="default: <source>/tests/footprint/figures.json")
    p.add_argument("--fix", action="store_true", help="rewrite the figures from the sources")
    p.add_argument("--self-test", action="store_true",
                   help="plant wrong and unregistered figures in copies; each must fail")
    a = p.parse_args()
    registry_path = a.registry or os.path.join(a.source, "tests", "footprint", "figures.json")
    with open(registry_path) as f:
        registry = json.load(f)
    src = Sources(a.source, a.build)
    problems = list(src.errors)
    if a.self_test and not problems:
        return self_test(a.source, registry, src)
    if not problems:
        files = ["README.md"] + sorted("docs/" + n for n in os.listdir(
            os.path.join(a.source, "docs")) if n.endswith(".md"))
        for root, _, names in os.walk(os.path.join(a.source, "include")):
            files += sorted(os.path.relpath(os.path.join(root, n), a.source)
                            for n in names if n.endswith(".hpp"))
        for rel in registry["files"]:
            if rel not in files:
                problems.append(f"{rel}: in figures.json but not a checked file")
        for rel in files:
            check_file(os.path.join(a.source, rel), rel, registry["files"].get(rel, []),
                       registry.get("blocks", {}), src, a.fix, problems)
    if problems:
        print("figures: " + str(len(problems)) + " problem(s):\n  " + "\n  ".join(problems),
              file=sys.stderr)
        if a.fix:
            print("figures: --fix rewrites measured figures only: register or remove the "
                  "others", file=sys.stderr)
        return 1
    print("figures: every figure agrees with its source")
    return 0


if __name__ == "__main__":
    sys.exit(main())
