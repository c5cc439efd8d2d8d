#!/usr/bin/env python3
"""Mutation testing of include/: applies one mutation at a time to a header, builds the
doctest tests that include it and runs them; a mutant those tests do not fail survives.
Reports every mutant (killed, survived, stillborn: it does not compile, or timed out) and the
score, killed / (killed + survived).

Usage: mutate.py --build DIR [--seed N] [--count N | --all | --site TEXT ...] [--files GLOB ...]
                 [--timeout S] [--report FILE] [--resume] [--list] [--all-tests]
                 [--parallel N] [--jobs N]

DIR: a configured Ninja build of this source tree with the target motionbus_tests (fast:
clang -O0 without debug information, no tools: cmake -S . -B build/mut -G Ninja
-DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None -DCMAKE_CXX_FLAGS=-O0
-DMOTIONBUS_BUILD_TOOLS=OFF). The source tree is never changed: the mutated header is written
to a directory of its own, searched first (-I) by the compile commands Ninja gives for the test
sources (`ninja -t commands`; checked at the start: a header there that cannot compile must
fail the build). The test sources that include the header come from Ninja's dependency log
(`ninja -t deps`), so no test case that can execute the header's code is left out (the library
is header-only: its code is compiled into the test sources that include it). Each test
source is self-contained (its test cases link with main.cpp alone), so they are tried one at a
time, the header's namesake test first (include/motionbus/modbus/server.hpp ->
tests/modbus/server_test.cpp), then the cheapest to compile: each is compiled with the mutant,
linked with main.cpp alone and run; the first that fails kills the mutant and the rest are not
built; a mutant that fails to compile or link in one of them is stillborn; one that passes
them all survives. The test cases run are those the whole suite would run for the header, each
in a binary whose every object that includes the header holds the mutant. --all-tests builds
all of them and runs the whole suite (the objects that do not include the header are the
build's own) instead.
--all takes every mutant, --seed and --count a sample, --site TEXT (repeatable) every mutant
whose listing line (`path:line: kind: before  ->  after`) contains TEXT: to check one again.
--parallel N builds and runs N mutants at once. Each mutant's record is appended to
REPORT.partial as it ends; --resume skips those already there whose header is unchanged (a
full run can be stopped and resumed). The report gives, for each mutant, its wall time, the
CPU time of its builds and runs (the finished child processes' user + system time: not
inflated by a shared machine's load), the test sources tried, and for each killed one the
test source and test cases that failed.

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
first COUNT taken.
"""
import argparse
import concurrent.futures
import glob
import hashlib
import json
import os
import random
import re
import resource
import shlex
import shutil
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
        users.setdefault(os.path.realpath(dep), set()).add(os.path.realpath(source))
    return {h: sorted(s) for h, s in users.items()}


class Suite:
    """The commands Ninja runs to build motionbus_tests, to be run again by hand: each test
    source's compile command (its object written elsewhere, a directory of mutated headers
    searched first) and the link command (other objects in its list)."""

    def __init__(self, build):
        self.build = build
        rc, out = run(["ninja", "-C", build, "-t", "commands", "tests/motionbus_tests"], 60)
        if rc != 0:
            raise SystemExit("mutate: ninja -t commands failed:\n" + out[-2000:])
        self.compile = {}  # source realpath -> argv
        self.objects = {}  # source realpath -> object path (relative to the build)
        self.link = None
        for line in out.splitlines():
            argv = shlex.split(line)
            if argv[:2] == [":", "&&"]:
                argv = argv[2:]
            if argv[-2:] == ["&&", ":"]:
                argv = argv[:-2]
            if "-c" in argv:
                src = os.path.realpath(os.path.join(build, argv[argv.index("-c") + 1]))
                keep = []
                skip = False
                for a in argv:
                    if skip:
                        skip = False
                    elif a in ("-MT", "-MF"):
                        skip = True
                    elif a != "-MD":
                        keep.append(a)
                self.objects[src] = keep[keep.index("-o") + 1]
                self.compile[src] = keep
            elif "-o" in argv and argv[argv.index("-o") + 1] == "tests/motionbus_tests":
                self.link = argv
        if self.link is None or not self.compile:
            raise SystemExit("mutate: no compile or link command of motionbus_tests in Ninja's")
        self.main = [o for s, o in self.objects.items() if s.endswith("/tests/main.cpp")]
        self.cost = {}  # object -> seconds its last build took (Ninja's log): cheap ones first
        try:
            with open(os.path.join(build, ".ninja_log"), encoding="utf-8") as f:
                for line in f:
                    part = line.split("\t")
                    if len(part) >= 4 and not line.startswith("#"):
                        self.cost[part[3]] = int(part[1]) - int(part[0])
        except OSError:
            pass

    def compile_cmd(self, source, overlay, obj):
        argv = list(self.compile[source])
        argv[argv.index("-o") + 1] = obj
        return argv[:1] + ["-I", overlay] + argv[1:]

    def link_cmd(self, replace, out):
        """The suite's link command with the objects in `replace` ({build object: new path})
        swapped in."""
        argv = []
        for a in self.link:
            argv.append(replace.get(a, a))
        argv[argv.index("-o") + 1] = out
        return argv

    def link_alone(self, objs, out):
        """main.cpp's object and `objs`: one test source's own test binary."""
        argv = [a for a in self.link if not a.endswith(".o")]
        at = argv.index("-o")
        return argv[:at] + self.main + objs + argv[at:at + 1] + [out] + argv[at + 2:]


def own_first(header, sources, suite):
    """Test sources in the order they are tried: the header's namesake test source first
    (include/motionbus/modbus/server.hpp -> tests/modbus/server_test.cpp), then the cheapest to
    compile."""
    stem = os.path.splitext(os.path.relpath(header, os.path.join(ROOT, "include", "motionbus")))[0]
    own = os.path.join(ROOT, "tests", stem + "_test.cpp")
    return sorted(sources, key=lambda s: (s != own, suite.cost.get(suite.objects[s], 0), s))


def mutate_one(job):
    """Build and run one mutant; in a worker process. Returns its result record."""
    (path, i, kind, before, after), suite, users, all_tests, timeout, work = job
    work = os.path.join(work, f"w{os.getpid()}")
    overlay = os.path.join(work, "overlay")
    rel = os.path.relpath(path, os.path.join(ROOT, "include"))
    shutil.rmtree(work, ignore_errors=True)
    os.makedirs(os.path.dirname(os.path.join(overlay, rel)))
    with open(path, encoding="utf-8") as f:
        lines = f.read().splitlines(keepends=True)
    lines[i] = after
    with open(os.path.join(overlay, rel), "w", encoding="utf-8") as f:
        f.write("".join(lines))
    t0 = time.time()
    build_cpu = run_cpu = 0.0
    status, failed, by, tried = "survived", [], None, 0
    sources = own_first(path, users.get(os.path.realpath(path), []), suite)

    def step(cmd):
        c0 = children_cpu()
        rc, out = run(cmd, timeout, cwd=suite.build)
        return rc, out, children_cpu() - c0

    groups = [sources] if all_tests else [[s] for s in sources]
    for group in groups:
        objs = {}
        for src in group:
            obj = os.path.join(work, f"{len(objs)}.o")
            rc, out, cpu = step(suite.compile_cmd(src, overlay, obj))
            build_cpu += cpu
            tried += 1
            if rc is None or rc != 0:
                status, by = ("timeout" if rc is None else "stillborn"), os.path.relpath(src, ROOT)
                break
            objs[suite.objects[src]] = obj
        if status != "survived":
            break
        binary = os.path.join(work, "tests")
        cmd = (suite.link_cmd(objs, binary) if all_tests
               else suite.link_alone(list(objs.values()), binary))
        rc, out, cpu = step(cmd)
        build_cpu += cpu
        if rc != 0:
            status, by = "stillborn", "link"
            break
        rc, out, cpu = step([binary, "--no-version"])
        run_cpu += cpu
        if rc is None or rc != 0:
            status = "timeout" if rc is None else "killed"
            by = "all" if all_tests else os.path.relpath(group[0], ROOT)
            failed = sorted(set(re.findall(r"^TEST CASE:\s+(.*)$", out, re.M)))
            break
    shutil.rmtree(work, ignore_errors=True)
    return {"where": f"{os.path.relpath(path, ROOT)}:{i + 1}", "kind": kind,
            "before": before.strip(), "after": after.strip(), "status": status,
            "by": by, "sources": f"{tried} of {len(sources)}",
            "seconds": round(time.time() - t0, 1), "build_cpu_s": round(build_cpu, 1),
            "run_cpu_s": round(run_cpu, 1), "failed": failed}


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
    ap.add_argument("--jobs", type=int, default=2,
                    help="build jobs of the unmutated build (default 2)")
    ap.add_argument("--parallel", type=int, default=1,
                    help="mutants built and run at once (default 1)")
    ap.add_argument("--all", action="store_true", help="every mutant, not a sample")
    ap.add_argument("--resume", action="store_true",
                    help="skip the mutants already in REPORT.partial (same header contents)")
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
    elif args.all:
        sample = everything
        print(f"mutate: all {len(everything)} mutants in {len(headers)} headers", flush=True)
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
    users = tests_including(build)
    if not users:
        print("mutate: no dependency log (ninja -t deps)", file=sys.stderr)
        return 2
    suite = Suite(build)
    work = os.path.join(build, "mutants")
    os.makedirs(work, exist_ok=True)
    # The directory of mutated headers must be searched first: a header there that cannot
    # compile must fail the build of a test source that includes it.
    probe = os.path.join(ROOT, "include", "motionbus", "core", "crc.hpp")
    probe_site = (probe, 0, "probe", "", "#error the overlay is searched first\n")
    r = mutate_one((probe_site, suite, users, False, args.timeout, work))
    if r["status"] != "stillborn":
        print("mutate: a mutated header is not seen by the test sources' builds",
              file=sys.stderr)
        return 2

    report = args.report or os.path.join(build, "mutants.json")
    partial = report + ".partial"  # one line a mutant, as each ends: --resume reads it
    digest = {}
    for h in headers:
        with open(h, "rb") as f:
            digest[h] = hashlib.sha1(f.read()).hexdigest()[:12]

    def key(site):
        return f"{digest[site[0]]} {listing(site)}"

    done = {}
    if args.resume and os.path.exists(partial):
        with open(partial, encoding="utf-8") as f:
            for line in f:
                rec = json.loads(line)
                done[rec["key"]] = rec
    elif os.path.exists(partial):
        os.remove(partial)
    results = [done[key(site)] for site in sample if key(site) in done]
    todo = [site for site in sample if key(site) not in done]
    if results:
        print(f"mutate: {len(results)} mutants resumed from {partial}", flush=True)
    started = time.time()
    jobs = [(site, suite, users, args.all_tests, args.timeout, work) for site in todo]
    with concurrent.futures.ProcessPoolExecutor(max_workers=args.parallel) as pool, \
            open(partial, "a", encoding="utf-8") as log:
        futures = {pool.submit(mutate_one, job): job[0] for job in jobs}
        for future in concurrent.futures.as_completed(futures):
            r = future.result()
            r["key"] = key(futures[future])
            log.write(json.dumps(r) + "\n")
            log.flush()
            results.append(r)
            print(f"[{len(results)}/{len(sample)}] {r['status']:9} {r['where']} {r['kind']}: "
                  f"{r['before']}  ->  {r['after']}  ({r['sources']} test sources; "
                  f"{r['seconds']:.1f} s; CPU {r['build_cpu_s']:.1f} s build "
                  f"+ {r['run_cpu_s']:.1f} s run)", flush=True)
            for name in r["failed"][:8]:
                print(f"      failed: {name}", flush=True)
    order = {key(site): n for n, site in enumerate(sample)}
    results.sort(key=lambda r: order[r["key"]])
    counts = {"killed": 0, "survived": 0, "stillborn": 0, "timeout": 0}
    for r in results:
        counts[r["status"]] += 1
    decided = counts["killed"] + counts["survived"]
    score = 100.0 * counts["killed"] / decided if decided else 0.0
    summary = {"seed": None if args.site else args.seed, "population": len(everything),
               "sample": len(sample), "counts": counts, "score": round(score, 1),
               "seconds": round(time.time() - started),
               "build_cpu_seconds": round(sum(r["build_cpu_s"] for r in results), 1),
               "run_cpu_seconds": round(sum(r["run_cpu_s"] for r in results), 1),
               "tests": "the whole suite" if args.all_tests
               else "each test source including the header, alone, until one fails"}
    with open(report, "w", encoding="utf-8") as f:
        json.dump({"summary": summary, "mutants": results}, f, indent=1)
    print(f"mutate: {counts['killed']} killed, {counts['survived']} survived, "
          f"{counts['stillborn']} stillborn, {counts['timeout']} timed out; "
          f"score {score:.1f} % of {decided}; CPU {summary['build_cpu_seconds']:.0f} s build + "
          f"{summary['run_cpu_seconds']:.0f} s run; report {report}")
    for r in results:
        if r["status"] == "survived":
            print(f"  SURVIVED {r['where']} {r['kind']}: {r['before']}  ->  {r['after']}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
