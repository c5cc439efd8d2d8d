#!/usr/bin/env python3
"""Mutation testing of include/: applies one mutation at a time to a header, rebuilds the
doctest suite (motionbus_tests) of a configured build and runs it; a mutant the suite does
not fail survives. Reports every mutant (killed, survived, stillborn: it does not compile,
or timed out) and the score, killed / (killed + survived).

Usage: mutate.py --build DIR [--seed N] [--count N] [--files GLOB ...] [--timeout S]
                 [--report FILE] [--list] [--site TEXT ...] [--all-tests] [--jobs N]

DIR: a configured build of this source tree with the target motionbus_tests (fast: gcc -O0,
no tools, e.g. cmake -S . -B build/mut -G Ninja -DCMAKE_CXX_COMPILER=g++
-DCMAKE_BUILD_TYPE=Debug -DCMAKE_CXX_FLAGS=-O0 -DMOTIONBUS_BUILD_TOOLS=OFF; ccache, when
installed, is used through CMAKE_CXX_COMPILER_LAUNCHER if the build sets it). Ninja rebuilds
only the test sources that include the mutated header, and only their test cases run (doctest
--source-file): the test sources come from Ninja's dependency log (`ninja -t deps`), so a test
case that can execute the header's code is never left out (the library is header-only: its code
is compiled into the test sources that include it). --all-tests runs the whole suite instead.
--site TEXT (repeatable) takes, instead of a sample, every mutant whose listing line
(`path:line: kind: before  ->  after`) contains TEXT: to check one mutant again.
The report gives, for each mutant, the wall time of its build and run and their CPU time
(the finished child processes' user + system time: not inflated by a shared machine's load),
and for each killed one the test cases that failed.

Mutations (on code lines: not comments, preprocessor lines or static_asserts), each site one
mutant:
  relational   a < b -> a <= b, <= -> <, > -> >=, >= -> > (binary, spaced as clang-format
               spaces them: not template brackets or shifts)
  equality     == -> !=, != -> ==
  boolean      && -> ||, || -> &&, `return true` <-> `return false`, `!x` -> `x` in a condition
  constant     an integer literal n -> n + 1 (off by one; not in array sizes of declarations)
  deletion     a statement that is a call, an increment or an assignment -> removed
  swap         f(a, b) -> f(b, a) for a call with two simple arguments
The sample: the sites of the chosen headers in a fixed order, shuffled with the seed, the
first COUNT taken. The header is restored after each mutant (and on any exit).
"""
import argparse
import glob
import json
import os
import random
import re
import resource
import subprocess
import sys
import time

ROOT = os.path.abspath(os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

BINARY = [
    ("relational", re.compile(r"(?<=\s)<(?=\s)"), "<="),
    ("relational", re.compile(r"(?<=\s)<=(?=\s)"), "<"),
    ("relational", re.compile(r"(?<=\s)>(?=\s)"), ">="),
    ("relational", re.compile(r"(?<=\s)>=(?=\s)"), ">"),
    ("equality", re.compile(r"(?<=\s)==(?=\s)"), "!="),
    ("equality", re.compile(r"(?<=\s)!=(?=\s)"), "=="),
    ("boolean", re.compile(r"(?<=\s)&&(?=\s)"), "||"),
    ("boolean", re.compile(r"(?<=\s)\|\|(?=\s)"), "&&"),
    ("boolean", re.compile(r"\breturn true;"), "return false;"),
    ("boolean", re.compile(r"\breturn false;"), "return true;"),
    ("boolean", re.compile(r"(?<=[(\s])!(?=[a-z_(])"), ""),
    ("constant", re.compile(r"(?<![\w.])(?:0x[0-9A-Fa-f]+|\d+)(?=[uUlL]*\b)(?![.\w])"), None),
]
STATEMENT = re.compile(r"^\s*(?:\+\+\w[\w.\[\]]*|\w[\w.\[\]>-]*\s*(?:\+\+|--|[+\-|&^]?=)[^=].*|"
                       r"[\w:.]+\([^;]*\));\s*(?://.*)?$")
SWAP = re.compile(r"\b(\w+)\((\w+), (\w+)\)")


def code_lines(text):
    """(index, line) for lines that hold code to mutate."""
    out = []
    in_block = False
    for i, line in enumerate(text.splitlines(keepends=True)):
        s = line.strip()
        if in_block:
            if "*/" in s:
                in_block = False
            continue
        if s.startswith("/*"):
            in_block = "*/" not in s
            continue
        if not s or s.startswith("//") or s.startswith("#") or "static_assert" in s:
            continue
        if s.endswith("\\") or (out and out[-1][1].rstrip().endswith("\\")):
            continue  # a preprocessor line continued
        if s.startswith("template") or s.startswith("using ") or s.startswith("namespace"):
            continue
        out.append((i, line))
    return out


def strip_comment(line):
    at = line.find("//")
    return (line[:at], line[at:]) if at >= 0 else (line.rstrip("\n"), "")


def sites(path):
    """Every mutant of one header: (path, line index, kind, original line, mutated line)."""
    with open(path, encoding="utf-8") as f:
        text = f.read()
    out = []
    for i, line in code_lines(text):
        code, comment = strip_comment(line)
        newline = "\n" if line.endswith("\n") else ""
        if '"' in code or "'" in code:
            continue  # no mutation inside literals
        for kind, pattern, repl in BINARY:
            for m in pattern.finditer(code):
                if kind == "constant":
                    if re.search(r"\w\s*\[\s*$", code[:m.start()]) and \
                            re.match(r"\s*\]\s*(?:=|;|\{)", code[m.end():]):
                        continue  # an array's size in its declaration
                    text_n = m.group(0)
                    value = int(text_n, 0) + 1
                    new = hex(value) if text_n.lower().startswith("0x") else str(value)
                else:
                    new = repl
                mutated = code[:m.start()] + new + code[m.end():]
                out.append((path, i, kind, line, mutated + comment + newline
                            if not comment else mutated + comment))
        if STATEMENT.match(code) and not code.strip().startswith("return"):
            indent = code[:len(code) - len(code.lstrip())]
            out.append((path, i, "deletion", line, indent + ";  // (deleted)" + newline))
        for m in SWAP.finditer(code):
            if m.group(2) != m.group(3):
                mutated = code[:m.start()] + f"{m.group(1)}({m.group(3)}, {m.group(2)})" + \
                    code[m.end():]
                out.append((path, i, "swap", line, mutated + comment +
                            ("" if comment else newline)))
    return out


def tests_including(build):
    """{header path: [test source path, ...]} from Ninja's dependency log of motionbus_tests."""
    rc, out = run(["ninja", "-C", build, "-t", "deps"], 60)
    if rc != 0:
        return None
    users = {}
    source = None
    for line in out.splitlines():
        if not line.startswith(" "):
            obj = line.split(":", 1)[0]
            source = None if "motionbus_tests.dir" not in obj else ""
            continue
        dep = line.strip()
        if source is None or not dep:
            continue
        if source == "":
            source = dep  # the first dependency is the source itself
            continue
        users.setdefault(os.path.realpath(dep), set()).add(source)
    return {h: sorted(s) for h, s in users.items()}


def children_cpu():
    """CPU seconds (user + system) of the finished child processes so far."""
    r = resource.getrusage(resource.RUSAGE_CHILDREN)
    return r.ru_utime + r.ru_stime


def run(cmd, timeout, cwd=None):
    try:
        p = subprocess.run(cmd, cwd=cwd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                           timeout=timeout, check=False)
        return p.returncode, p.stdout.decode(errors="replace")
    except subprocess.TimeoutExpired:
        return None, "timeout"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", required=True)
    ap.add_argument("--seed", type=int, default=28)
    ap.add_argument("--count", type=int, default=300)
    ap.add_argument("--files", nargs="*", default=["include/motionbus/**/*.hpp"])
    ap.add_argument("--timeout", type=float, default=300, help="seconds per build and per run")
    ap.add_argument("--report", default=None, help="JSON report (default: BUILD/mutants.json)")
    ap.add_argument("--list", action="store_true", help="list the sample, mutate nothing")
    ap.add_argument("--site", action="append", default=[],
                    help="every mutant whose listing line contains TEXT, instead of a sample")
    ap.add_argument("--all-tests", action="store_true",
                    help="run the whole suite, not only the test sources including the header")
    ap.add_argument("--jobs", type=int, default=2, help="build jobs (default 2)")
    args = ap.parse_args()
    build = os.path.abspath(args.build)
    headers = sorted({p for g in args.files
                      for p in glob.glob(os.path.join(ROOT, g), recursive=True)})
    everything = [s for h in headers for s in sites(h)]
    def listing(site):
        path, i, kind, before, after = site
        return f"{os.path.relpath(path, ROOT)}:{i + 1}: {kind}: {before.strip()}  ->  " \
            f"{after.strip()}"

    if args.site:
        sample = [s for s in everything if any(t in listing(s) for t in args.site)]
        print(f"mutate: {len(everything)} mutants in {len(headers)} headers; "
              f"{len(sample)} selected by --site", flush=True)
    else:
        rng = random.Random(args.seed)
        sample = list(everything)
        rng.shuffle(sample)
        sample = sample[:args.count]
        print(f"mutate: {len(everything)} mutants in {len(headers)} headers; "
              f"sample of {len(sample)} (seed {args.seed})", flush=True)
    if args.list:
        for site in sample:
            print(listing(site))
        return 0
    tests = os.path.join(build, "tests", "motionbus_tests")
    build_cmd = ["cmake", "--build", build, "--target", "motionbus_tests", "-j", str(args.jobs)]
    rc, out = run(build_cmd, args.timeout * 4)
    if rc != 0:
        print("mutate: the unmutated build fails:\n" + out[-3000:], file=sys.stderr)
        return 2
    rc, out = run([tests, "--no-version"], args.timeout)
    if rc != 0:
        print("mutate: the unmutated tests fail:\n" + out[-3000:], file=sys.stderr)
        return 2
    users = None if args.all_tests else tests_including(build)
    if users is None and not args.all_tests:
        print("mutate: no dependency log (ninja -t deps): the whole suite runs", file=sys.stderr)
    results = []
    counts = {"killed": 0, "survived": 0, "stillborn": 0, "timeout": 0}
    started = time.time()
    for n, (path, i, kind, before, after) in enumerate(sample, start=1):
        run_cmd = [tests, "--no-version"]
        if users is not None:
            sources = users.get(os.path.realpath(path), [])
            # doctest matches a test case's file name against each comma-separated pattern
            run_cmd.append("--source-file=" + ",".join(
                "*" + os.path.relpath(src, ROOT) for src in sources) if sources
                else "--source-file=-none-")
        build_s = run_s = 0.0
        failed = []
        cpu0 = children_cpu()
        build_cpu = 0.0
        with open(path, encoding="utf-8") as f:
            original = f.read()
        lines = original.splitlines(keepends=True)
        lines[i] = after
        try:
            with open(path, "w", encoding="utf-8") as f:
                f.write("".join(lines))
            t0 = time.time()
            rc, out = run(build_cmd, args.timeout)
            build_s = time.time() - t0
            build_cpu = children_cpu() - cpu0
            if rc is None:
                status = "timeout"
            elif rc != 0:
                status = "stillborn"
            else:
                t0 = time.time()
                rc, out = run(run_cmd, args.timeout)
                run_s = time.time() - t0
                status = "timeout" if rc is None else ("killed" if rc != 0 else "survived")
                if status == "killed":  # the test cases that failed: which test kills it
                    failed = sorted(set(re.findall(r"^TEST CASE:\s+(.*)$", out, re.M)))
        finally:
            with open(path, "w", encoding="utf-8") as f:
                f.write(original)
        cpu_s = children_cpu() - cpu0  # load-independent, unlike the wall times
        run_cpu = cpu_s - build_cpu
        counts[status] += 1
        where = f"{os.path.relpath(path, ROOT)}:{i + 1}"
        results.append({"where": where, "kind": kind, "before": before.strip(),
                        "after": after.strip(), "status": status,
                        "build_s": round(build_s, 1), "run_s": round(run_s, 1),
                        "build_cpu_s": round(build_cpu, 1), "run_cpu_s": round(run_cpu, 1),
                        "failed": failed})
        print(f"[{n}/{len(sample)}] {status:9} {where} {kind}: {before.strip()}  ->  "
              f"{after.strip()}  (build {build_s:.1f} s, run {run_s:.1f} s; CPU {build_cpu:.1f} s "
              f"+ {run_cpu:.1f} s)",
              flush=True)
        for name in failed[:8]:
            print(f"      failed: {name}", flush=True)
    # the headers restored: rebuild once so that the build matches the sources again
    run(build_cmd, args.timeout * 4)
    decided = counts["killed"] + counts["survived"]
    score = 100.0 * counts["killed"] / decided if decided else 0.0
    summary = {"seed": None if args.site else args.seed, "population": len(everything),
               "sample": len(sample), "counts": counts, "score": round(score, 1),
               "seconds": round(time.time() - started),
               "build_seconds": round(sum(r["build_s"] for r in results), 1),
               "run_seconds": round(sum(r["run_s"] for r in results), 1),
               "build_cpu_seconds": round(sum(r["build_cpu_s"] for r in results), 1),
               "run_cpu_seconds": round(sum(r["run_cpu_s"] for r in results), 1),
               "tests": "all" if users is None else "the test sources including the header"}
    report = args.report or os.path.join(build, "mutants.json")
    with open(report, "w", encoding="utf-8") as f:
        json.dump({"summary": summary, "mutants": results}, f, indent=1)
    print(f"mutate: {counts['killed']} killed, {counts['survived']} survived, "
          f"{counts['stillborn']} stillborn, {counts['timeout']} timed out; "
          f"score {score:.1f} % of {decided}; report {report}")
    for r in results:
        if r["status"] == "survived":
            print(f"  SURVIVED {r['where']} {r['kind']}: {r['before']}  ->  {r['after']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
