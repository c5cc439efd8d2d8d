#!/usr/bin/env python3
"""Line and branch coverage of include/ from a MOTIONBUS_COVERAGE build, after its tests ran.

Usage: coverage_check.py <source root> <coverage build dir> [--gcov-json FILE]

Runs gcov on every .gcda file of the build (`gcov --stdout --json-format`, gcov's own JSON:
one document per object file; or, with --gcov-json, reads such documents from FILE, one a line:
the self-test, tests/checks/coverage_gate), merges them, writes <build>/coverage-report.txt
(totals, each header, every uncovered line with its justification, every line with untaken
branches) and <build>/coverage.json (the merged lines and branches of include/), prints the
totals, and fails
  - when a line of include/ that no test executed carries no justification,
  - when a branch of include/ that no test took carries no justification (below), or
  - when the branch coverage of include/ is below BRANCH_MIN (90 %).

Lines and branches are gcov's, read from its JSON rather than through gcovr: gcovr 5.2 reads
gcov's text output, where the branches of some template instances are lost (an instance the
linker kept, whose branches the tests take, showed them untaken). For each object file, gcov's
JSON has a record of a line for each function instance with code on it (a template's
instances, a constructor's variants), with that instance's count and its branches in the order
of the line's blocks, each with its count and its `fallthrough` and `throw` flags; the lines
of functions that are not grouped (one function starting at their first line) come as one
record for the object file, the branches of each such function on the line appended one
function after another. Records are merged per line of a header, over every object file and
every instance:
  - the line's count is the sum of its records' counts; it is executed when one of them is;
  - branches: first each record loses its throw edges (below); its shape is then the sequence
    of its branches' fallthrough flags. Records of one shape are the same code of the line
    (the same function in another object file, or another instance of a template making the
    same decisions there): they are paired by position, and a position is taken when any
    record of the shape took it (a per-line union over instances and object files of each
    branch position). A record whose shape is k copies of a shorter shape of the line (a
    record of k functions appended, e.g. a lambda's instances) folds onto it, its position i
    onto i mod the shorter length; the report lists each fold. A fold or a pairing credits a
    decision with another's outcome only where instances of a line differ in code (a
    condition the compiler folded in one, an `if constexpr` that empties a branch in one):
    the listed folds are to be checked by hand. Any other shapes of a line count on their
    own, each taken only by records of that shape.
    The line's branches are its shapes' positions.
Two kinds of branch are not counted, with the meaning gcovr's options gave them:
  - unreachable: every branch of a line that holds no code of its own, whose text outside
    comments is empty, `{`, `}` or `{}` (gcovr's --exclude-unreachable-branches): gcc gives
    such a line the edges of the code around it (a closing brace: the scope's exits,
    destructors), counted where that code is; such a line is not counted as a line either
    when no test executed it (a `{`, `}`, `else` or comment line, as gcovr);
  - throw: a branch gcov flags `throw`, the edge to the exception path of a call that may
    throw (gcovr's --exclude-throw-branches), and with it the call's return edge, the branch
    listed just before it: with its throw edge gone it is no decision, taken whenever the
    line runs (gcovr counted it). include/ never throws, but the tests' doctest checks, their
    callbacks and the standard library may: those edges are the compiler's, not the
    library's decisions.
Every other branch counts.

A justification is a comment in the header itself:
  ... code ...  // coverage: <why no test reaches this line>
on the uncovered line, or on a comment line of its own directly above it; or a region
  // coverage-begin: <why>
  ... lines ...
  // coverage-end
A justification on a line that the tests do execute is stale and fails the check too.
An unexecuted line's justification covers its branches too. An uncovered branch of an executed
line is justified by
  ... code ...  // coverage-branch: <why no test takes this branch>
(on the line, or on a comment line of its own directly above it); a branch justification on a
line whose branches are all taken is stale and fails the check. An untaken branch with no
justification fails the check (a new decision needs a test that takes each of its ways, or a
reason in the header why none can); the justified ones still count against BRANCH_MIN, which
stays as the floor of the figure itself.
"""
import json
import os
import re
import subprocess
import sys

BRANCH_MIN = 90.0
MARK = re.compile(r"//\s*coverage:\s*(\S.*)$")
BRANCH_MARK = re.compile(r"//\s*coverage-branch:\s*(\S.*)$")
BEGIN = re.compile(r"//\s*coverage-begin:\s*(\S.*)$")
END = re.compile(r"//\s*coverage-end\b")
CPP_COMMENT = re.compile(r"//.*$")
C_COMMENT = re.compile(r"/\*.*?\*/")
GCOV = ["gcov", "--stdout", "--json-format", "--branch-probabilities"]
GCOV_BATCH = 40


def code_text(text):
    """A source line without its comments and blanks."""
    return C_COMMENT.sub("", CPP_COMMENT.sub("", text)).replace(" ", "").strip()


def gcov_documents(build):
    """gcov's JSON documents, one for each .gcda file of the build."""
    gcda = []
    for parent, _, names in os.walk(build):
        gcda += [os.path.join(parent, n) for n in names if n.endswith(".gcda")]
    gcda.sort()
    docs = []
    for i in range(0, len(gcda), GCOV_BATCH):
        p = subprocess.run(GCOV + gcda[i:i + GCOV_BATCH], cwd=build, capture_output=True,
                           text=True, check=False)
        if p.returncode != 0:
            raise RuntimeError(f"gcov failed ({p.returncode}): {p.stderr.strip()}")
        docs += [json.loads(t) for t in p.stdout.splitlines() if t.strip()]
    return docs


def decisions(branches):
    """A record's branches without each throw edge and the return edge it follows (the two
    out-edges of a call that may throw)."""
    out = []
    i = 0
    while i < len(branches):
        if i + 1 < len(branches) and branches[i + 1].get("throw"):
            i += 2
        elif branches[i].get("throw"):
            i += 1
        else:
            out.append(branches[i])
            i += 1
    return out


def merge(docs, root, folds):
    """Header (relative to root, under include/) -> line number -> (count, branches): the
    records of every document and instance merged as the docstring says; branches a list of
    their counts (unreachable and throw branches left out). Each fold of a record's shape onto
    a shorter one is appended to `folds`."""
    include = os.path.join(root, "include") + os.sep
    records = {}
    for doc in docs:
        cwd = doc.get("current_working_directory", root)
        for entry in doc["files"]:
            path = os.path.normpath(os.path.join(cwd, entry["file"]))
            if not path.startswith(include):
                continue
            per_file = records.setdefault(os.path.relpath(path, root), {})
            for rec in entry["lines"]:
                per_file.setdefault(rec["line_number"], []).append(rec)
    out = {}
    for path, lines in records.items():
        with open(os.path.join(root, path), encoding="utf-8") as f:
            src = f.read().splitlines()
        merged = {}
        for n, recs in lines.items():
            count = sum(r["count"] for r in recs)
            text = code_text(src[n - 1]) if n <= len(src) else ""
            if count == 0 and text in ("", "{", "}", "else"):
                continue  # no code of its own, not executed: not a line
            shapes = {}
            for r in recs:
                kept = decisions(r["branches"])
                shape = tuple(bool(b.get("fallthrough")) for b in kept)
                if not shape:
                    continue
                counts = shapes.setdefault(shape, [0] * len(shape))
                for i, b in enumerate(kept):
                    counts[i] += b["count"]
            bases = {}
            for shape in sorted(shapes, key=lambda sh: (len(sh), sh)):
                base = next((b for b in bases if len(shape) % len(b) == 0
                             and shape == b * (len(shape) // len(b))), None)
                if base is None:
                    bases[shape] = list(shapes[shape])
                else:
                    folds.append(f"{path}:{n}: {len(shape)} branches folded onto {len(base)}")
                    for i, c in enumerate(shapes[shape]):
                        bases[base][i % len(base)] += c
            branches = []
            if text not in ("", "{", "}", "{}"):  # unreachable: a line with no code
                for shape in sorted(bases, key=lambda sh: (len(sh), sh)):
                    branches += bases[shape]
            merged[n] = (count, branches)
        out[path] = merged
    return out


def justifications(lines):
    """Line number -> reason for every line a justification covers, and the single-line
    markers as (marker line, line it justifies) pairs (for the stale check)."""
    out = {}
    marks = []
    region = None
    for i, text in enumerate(lines, start=1):
        begin = BEGIN.search(text)
        if begin:
            region = begin.group(1)
            continue
        if END.search(text):
            region = None
            continue
        if region is not None:
            out[i] = region
        m = MARK.search(text)
        if m:
            # a comment line of its own applies to the next line
            target = i + 1 if text.strip().startswith("//") else i
            out[target] = m.group(1)
            marks.append((i, target))
    return out, marks


def branch_justifications(lines):
    """Line number -> (marker line, reason) for every `coverage-branch:` marker."""
    out = {}
    for i, text in enumerate(lines, start=1):
        m = BRANCH_MARK.search(text)
        if m:
            target = i + 1 if text.strip().startswith("//") else i
            out[target] = (i, m.group(1))
    return out


def main():
    args = sys.argv[1:]
    given = None
    if len(args) == 4 and args[2] == "--gcov-json":
        given = args[3]
        args = args[:2]
    if len(args) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    root = os.path.abspath(args[0])
    build = os.path.abspath(args[1])
    try:
        if given is not None:
            with open(given, encoding="utf-8") as f:
                docs = [json.loads(t) for t in f if t.strip()]
        else:
            docs = gcov_documents(build)
    except (OSError, ValueError, RuntimeError) as e:
        print(f"coverage: no gcov data: {e}", file=sys.stderr)
        return 1
    folds = []
    files = merge(docs, root, folds)
    if not files:
        print("coverage: no gcov data for include/ (did the tests run?)", file=sys.stderr)
        return 1
    with open(os.path.join(build, "coverage.json"), "w", encoding="utf-8") as f:
        json.dump({"files": [{"file": path, "lines": [
            {"line_number": n, "count": c, "branches": [{"count": b} for b in br]}
            for n, (c, br) in sorted(lines.items())]} for path, lines in sorted(files.items())]},
            f)
    total_lines = total_hit = total_br = total_br_hit = 0
    rows = []
    problems = []
    justified = []
    branch_justified = []
    branch_open = []
    for path in sorted(files):
        with open(os.path.join(root, path), encoding="utf-8") as f:
            src = f.read().splitlines()
        why, marks = justifications(src)
        branch_why = branch_justifications(src)
        lines = files[path]
        executed = {n for n, (count, _) in lines.items() if count > 0}
        missed = sorted(n for n, (count, _) in lines.items() if count == 0)
        branches = [b for _, br in lines.values() for b in br]
        br_hit = sum(1 for b in branches if b > 0)
        total_lines += len(lines)
        total_hit += len(executed)
        total_br += len(branches)
        total_br_hit += br_hit
        rows.append((path, len(lines), len(executed), len(branches), br_hit))
        for n in missed:
            if n in why:
                justified.append(f"{path}:{n}: {why[n]}")
            else:
                problems.append(f"{path}:{n}: not executed by any test and not justified: "
                                f"{src[n - 1].strip()}")
        for at, target in marks:
            if target in executed:
                problems.append(f"{path}:{at}: stale justification (line {target} is executed)")
        for n, (count, br) in sorted(lines.items()):
            untaken = sum(1 for b in br if b == 0)
            if n in branch_why and untaken == 0:
                problems.append(f"{path}:{branch_why[n][0]}: stale branch justification "
                                f"(every branch of line {n} is taken)")
            if untaken == 0:
                continue
            where = f"{path}:{n}: {untaken} of {len(br)} branches not taken"
            if n in why and count == 0:
                branch_justified.append(f"{where} (line not executed: {why[n]})")
            elif n in branch_why:
                branch_justified.append(f"{where}: {branch_why[n][1]}")
            else:
                branch_open.append(f"{where}: {src[n - 1].strip()}")
                problems.append(f"{where} and not justified: {src[n - 1].strip()}")

    def pct(a, b):
        return 100.0 * a / b if b else 100.0

    report = [f"motionbus coverage of include/ (gcov, -O0, every test of the coverage build)",
              f"lines:    {pct(total_hit, total_lines):.1f} % ({total_hit} of {total_lines})",
              f"branches: {pct(total_br_hit, total_br):.1f} % ({total_br_hit} of {total_br})",
              "", f"{'header':<48} {'lines':>14} {'branches':>16}"]
    for path, n, hit, nb, bhit in rows:
        report.append(f"{path:<48} {pct(hit, n):6.1f} % {hit:>4}/{n:<4} "
                      f"{pct(bhit, nb):6.1f} % {bhit:>4}/{nb:<4}")
    report += ["", f"uncovered lines justified in the headers: {len(justified)}"] + justified
    report += ["", f"lines with untaken branches, justified in the headers: "
               f"{len(branch_justified)}"] + branch_justified
    report += ["", f"lines with untaken branches, not justified: {len(branch_open)}"] + branch_open
    report += ["", f"records folded onto a shorter shape of their line (k copies of it): "
               f"{len(folds)}"] + sorted(set(folds))
    branch_pct = pct(total_br_hit, total_br)
    if branch_pct < BRANCH_MIN:
        problems.append(f"branch coverage of include/ {branch_pct:.1f} % is below "
                        f"{BRANCH_MIN:.0f} % ({total_br_hit} of {total_br} branches taken)")
    if problems:
        report += ["", f"problems: {len(problems)}"] + problems
    with open(os.path.join(build, "coverage-report.txt"), "w", encoding="utf-8") as f:
        f.write("\n".join(report) + "\n")
    print("\n".join(report[:3]))
    where = os.path.join(build, "coverage-report.txt")
    if problems:
        print(f"coverage: {len(problems)} problems (below); report in {where}")
        print("\n".join(problems), file=sys.stderr)
        return 1
    print(f"coverage: branches at or above {BRANCH_MIN:.0f} %; {len(justified)} uncovered lines "
          f"and {len(branch_justified)} lines with untaken branches, each justified; "
          f"report in {where}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
