#!/usr/bin/env python3
"""Mutation testing of include/: applies one mutation at a time to a header, builds the tests
of the test command that include it and runs them; a mutant they do not fail survives.
Reports every mutant (killed, survived, stillborn: it does not compile, or timed out) and the
score, killed / (killed + survived).

Usage: mutate.py --build DIR [--seed N] [--count N | --all | --site TEXT ...] [--files GLOB ...]
                 [--timeout S] [--report FILE] [--records FILE] [--resume] [--list]
                 [--parallel N] [--jobs N] [--run-factor X] [--run-floor S]
       mutate.py --summary --records FILE [--files GLOB ...]

DIR: a configured Ninja build of this source tree (fast: clang -O0 without debug information,
no tools: cmake -S . -B build/mut -G Ninja -DCMAKE_CXX_COMPILER=clang++ -DCMAKE_BUILD_TYPE=None
-DCMAKE_CXX_FLAGS=-O0 -DMOTIONBUS_BUILD_TOOLS=OFF). The tests: those ctest lists with the
labels unit, c_api, interop or example whose command runs a program of the build (the doctest
suite, the static_assert suites, the fuzz corpus replays, the C API test, the differential
tests against libmodbus and pymodbus, the examples; not the checks that run a compiler or a
script of their own: compile-fail checks, README snippets, warnings, packaging, the CLI's and
Python's tests, the firmware under QEMU). The source tree is never changed: the mutated header
is written to a directory of its own, searched first (-I) by the compile commands Ninja gives
for the objects (`ninja -t commands`; checked at the start: a header there that cannot
compile must fail the build). The objects that include the header come from Ninja's
dependency log (`ninja -t deps`), so no test that can execute the header's code is left out
(the library is header-only: its code is compiled into what includes it). Each doctest source
is self-contained (its test cases link with main.cpp alone), so the tests are tried one at a
time: the header's namesake doctest source first (include/motionbus/modbus/server.hpp ->
tests/modbus/server_test.cpp), the other doctest sources, then the other tests, each group
cheapest to rebuild first; each has its objects that include the header compiled with the
mutant, is linked (a program of its own; the project's static libraries by their objects)
and run as ctest runs it; the first that fails kills the mutant and the rest are not built; a
mutant that fails to compile or link is stillborn; one that passes them all survives; one
whose run of a test takes more than --run-factor times that test's run without the mutant
(measured at the start; at least --run-floor seconds, at most --timeout) timed out (a loop
the mutant made endless: before these options, each cost the whole --timeout). A test
whose rebuilt objects the mutant leaves byte for byte as the build has them is not linked or
run again: its programs are those that passed at the start ("unchanged" counts such tests).
--all takes every mutant, --seed and --count a sample, --site TEXT (repeatable) every mutant
whose listing line (`path:line: kind: before  ->  after`) contains TEXT: to check one again.
--parallel N builds and runs N mutants at once. Each mutant's record is appended to the
records file (--records; REPORT.partial unless named) as it ends; --resume skips those already
there whose header's code is unchanged (a full run can be stopped and resumed; a record's key
holds the digest of its header's text without comments, line breaks kept, so a comment edited
without moving a line keeps the header's records, and any other change records it again). The full run keeps its
records in docs/mutation/records.jsonl, committed as it goes (a records file named with
--records is never emptied: without --resume the script refuses one that exists): a run longer than a session goes
on in the next from what was committed. --summary reads a records file and builds nothing: for
each header its mutants today, those recorded for its present contents, their statuses and
score, then every survivor. The report gives, for each mutant, its wall time, the
CPU time of its builds and runs (the finished child processes' user + system time: not
inflated by a shared machine's load), the tests tried, and for each killed one the test and
the test cases (or the last line of output) that failed.

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
    continued = False  # the line before ends with a backslash: this one continues it
    for i, line in enumerate(text.splitlines(keepends=True)):
        s = line.strip()
        if continued:
            continued = s.endswith("\\")
            continue  # a preprocessor line continued (a macro's body, an #if's condition)
        if in_block:
            if "*/" in s:
                in_block = False
            continue
        if s.startswith("/*"):
            in_block = "*/" not in s
            continue
        if s.startswith("#"):
            continued = s.endswith("\\")
            continue
        if not s or s.startswith("//") or "static_assert" in s:
            continue
        if s.startswith("template") or s.startswith("using ") or s.startswith("namespace"):
            continue
        out.append((i, line))
    return out


# A string or character literal (kept), or a comment (dropped).
LITERAL_OR_COMMENT = re.compile(r"""'(?:\\.|[^'\\\n])*'|"(?:\\.|[^"\\\n])*"|//[^\n]*|/\*.*?\*/""",
                                re.S)


def code_digest(text):
    """A header's key in the records: the digest of its text without comments (a comment's line
    breaks kept, trailing blanks dropped), so that a comment edited without moving a line leaves
    the header's records standing; any change to code, or a line added or removed, changes it."""
    def keep(m):
        s = m.group(0)
        return s if s[0] in "\"'" else "\n" * s.count("\n")
    code = "\n".join(line.rstrip() for line in LITERAL_OR_COMMENT.sub(keep, text).split("\n"))
    return hashlib.sha1(code.encode("utf-8")).hexdigest()[:12]


def code_listing(site):
    """`path:line: kind: before  ->  after` with the lines' comments dropped: a mutant's key
    ("v3": the tests of the test command, a header's code without its comments)."""
    path, i, kind, before, after = site
    return f"{os.path.relpath(path, ROOT)}:{i + 1}: {kind}: " \
        f"{strip_comment(before)[0].strip()}  ->  {strip_comment(after)[0].strip()}"


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


def objects_including(build):
    """{header realpath: {object path relative to the build, ...}} from Ninja's dependency log."""
    rc, out = run(["ninja", "-C", build, "-t", "deps"], 60)
    if rc != 0:
        return None
    users = {}
    obj = None
    for line in out.splitlines():
        if not line.startswith(" "):
            obj = line.split(":", 1)[0]
            continue
        dep = line.strip()
        if obj and dep:
            users.setdefault(os.path.realpath(os.path.join(build, dep)), set()).add(obj)
    return users


def split_command(line):
    argv = shlex.split(line)
    if argv[:2] == [":", "&&"]:
        argv = argv[2:]
    if argv[-2:] == ["&&", ":"]:
        argv = argv[:-2]
    return argv


class Program:
    """One executable of the build, as Ninja builds it: each object's compile command (to be run
    again with a directory of mutated headers searched first and the object written elsewhere)
    and the link command, the objects of the project's static libraries listed in place of the
    libraries (so that a mutated object can take its place)."""

    def __init__(self, build, target):
        self.build, self.target = build, target
        rc, out = run(["ninja", "-C", build, "-t", "commands", target], 60)
        if rc != 0:
            raise SystemExit(f"mutate: ninja -t commands {target} failed:\n" + out[-2000:])
        self.compile = {}  # object -> argv
        self.source = {}   # object -> source realpath
        archives = {}      # library -> its objects
        self.link = None
        for line in out.splitlines():
            if " qc " in line:  # a static library: rm, ar qc LIB OBJECTS, ranlib
                argv = shlex.split(line)
                at = argv.index("qc")
                archives[argv[at + 1]] = [a for a in argv[at + 2:] if a.endswith(".o")]
                continue
            argv = split_command(line)
            if "-c" in argv:
                keep, skip = [], False
                for a in argv:
                    if skip:
                        skip = False
                    elif a in ("-MT", "-MF"):
                        skip = True
                    elif a != "-MD":
                        keep.append(a)
                obj = keep[keep.index("-o") + 1]
                self.compile[obj] = keep
                self.source[obj] = os.path.realpath(
                    os.path.join(build, keep[keep.index("-c") + 1]))
            elif "-o" in argv and argv[argv.index("-o") + 1] == target:
                self.link = []
                for a in argv:
                    self.link.extend(archives.get(a, [a]))
        if self.link is None:
            raise SystemExit(f"mutate: no link command of {target} in Ninja's")
        self.objects = [a for a in self.link if a in self.compile]

    def compile_cmd(self, obj, overlay, out):
        argv = list(self.compile[obj])
        argv[argv.index("-o") + 1] = out
        return argv[:1] + ["-I", overlay] + argv[1:]

    def link_cmd(self, objects, out):
        """The link command with `objects` (the program's objects, some of them replaced) in
        place of its own."""
        argv = []
        for a in self.link:
            if a in self.compile:
                if objects is not None:
                    argv.extend(objects)
                    objects = None
            else:
                argv.append(a)
        argv[argv.index("-o") + 1] = out
        return argv


class Suite:
    """What the mutants are tried against: the test command's tests that run programs built
    from the library's headers, as ctest lists them (labels unit, c_api, interop, example), each
    with the programs its command names. The doctest suite's test sources are tried one by one
    (each links with main.cpp alone); every other test is run as ctest runs it, its programs
    rebuilt with the mutant."""

    LABELS = {"unit", "c_api", "interop", "example"}

    def __init__(self, build):
        self.build = build
        rc, out = run(["ctest", "--test-dir", build, "--show-only=json-v1"], 60)
        if rc != 0:
            raise SystemExit("mutate: ctest --show-only failed:\n" + out[-2000:])
        self.tests = []     # (name, argv, working directory, timeout, [program targets])
        self.programs = {}  # target -> Program
        for t in json.loads(out)["tests"]:
            props = {p["name"]: p["value"] for p in t.get("properties", [])}
            if not self.LABELS & set(props.get("LABELS", [])) or not t.get("command"):
                continue
            targets = []
            for a in t["command"]:
                rel = os.path.relpath(a, build) if os.path.isabs(a) else None
                if rel and not rel.startswith("..") and os.access(a, os.X_OK) \
                        and os.path.isfile(a):
                    targets.append(rel)
            if not targets:
                continue  # a check that builds nothing of its own (a compiler run, a script)
            for target in targets:
                if target not in self.programs:
                    self.programs[target] = Program(build, target)
            self.tests.append((t["name"], t["command"], props.get("WORKING_DIRECTORY", build),
                               props.get("TIMEOUT"), targets))
        self.unit = self.programs.get("tests/motionbus_tests")
        if self.unit is None:
            raise SystemExit("mutate: no test runs tests/motionbus_tests")
        self.main = [o for o in self.unit.objects
                     if self.unit.source[o].endswith(os.sep + os.path.join("tests", "main.cpp"))]
        self.seconds = {}  # test name -> wall seconds of its run without a mutant
        self.factor, self.floor = 10.0, 10.0  # a mutant's run may take that many times more
        self.cost = {}  # object -> milliseconds its last build took (Ninja's log)
        try:
            with open(os.path.join(build, ".ninja_log"), encoding="utf-8") as f:
                for line in f:
                    part = line.split("\t")
                    if len(part) >= 4 and not line.startswith("#"):
                        self.cost[part[3].strip()] = int(part[1]) - int(part[0])
        except OSError:
            pass

    def run_limit(self, label, argv):
        """The seconds a mutant's run of a test may take before it counts as a time-out: the
        factor times the test's run without a mutant (a doctest source alone: the whole
        suite's), at least the floor."""
        base = self.seconds.get(label if argv is not None else None, self.seconds.get(None))
        return max(self.floor, self.factor * (base or self.floor))

    def plan(self, header, users):
        """The steps for a mutant of `header`: (label, [(program, [objects to rebuild])], argv
        with the programs as placeholders, working directory, timeout), in the order tried: the
        header's namesake test source, the other doctest sources, then the other tests, each
        group cheapest to rebuild first."""
        objs = users.get(os.path.realpath(header), set())
        stem = os.path.splitext(os.path.relpath(
            header, os.path.join(ROOT, "include", "motionbus")))[0]
        own = os.path.join(ROOT, "tests", stem + "_test.cpp")
        steps = []
        for obj in self.unit.objects:
            if obj in objs and obj not in self.main:
                src = self.unit.source[obj]
                steps.append(((src != own, 0, self.cost.get(obj, 0)), os.path.relpath(src, ROOT),
                              [("tests/motionbus_tests", [obj])], None, None, None))
        for name, argv, cwd, timeout, targets in self.tests:
            if targets == ["tests/motionbus_tests"]:
                continue
            rebuild = [(t, [o for o in self.programs[t].objects if o in objs]) for t in targets]
            if any(r for _, r in rebuild):
                cost = sum(self.cost.get(o, 0) for _, r in rebuild for o in r)
                steps.append(((True, 1, cost), name, rebuild, argv, cwd, timeout))
        steps.sort(key=lambda s: s[0])
        return [s[1:] for s in steps]


def mutate_one(job):
    """Build and run one mutant; in a worker process. Returns its result record."""
    (path, i, kind, before, after), suite, users, timeout, work = job
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
    status, failed, by, tried, same = "survived", [], None, 0, 0
    steps = suite.plan(path, users)
    built = {}  # object -> its mutated build (an object shared by two programs is built once)
    changed = {}  # object -> whether the mutant's build of it differs from the build's own

    def step(cmd, cwd, limit):
        c0 = children_cpu()
        rc, out = run(cmd, limit, cwd=cwd)
        return rc, out, children_cpu() - c0

    for label, rebuild, argv, cwd, limit in steps:
        tried += 1
        binaries = {}
        for target, objs in rebuild:
            program = suite.programs[target]
            for obj in objs:
                if obj in built:
                    continue
                out_obj = os.path.join(work, f"{len(built)}.o")
                rc, out, cpu = step(program.compile_cmd(obj, overlay, out_obj), suite.build,
                                    timeout)
                build_cpu += cpu
                if rc is None or rc != 0:
                    status = "timeout" if rc is None else "stillborn"
                    break
                built[obj] = out_obj
                changed[obj] = contents(out_obj) != contents(os.path.join(suite.build, obj))
            if status != "survived":
                break
        # Objects the mutant leaves byte for byte as the build has them make the programs that
        # passed at the start (the mutated code is not in them): not linked or run again.
        if status == "survived" and any(changed[o] for _, objs in rebuild for o in objs):
            for target, objs in rebuild:
                program = suite.programs[target]
                binary = os.path.join(work, f"p{len(binaries)}")
                if argv is None:  # one doctest source alone
                    objects = suite.main + [built[o] for o in objs]
                else:
                    objects = [built.get(o, os.path.join(suite.build, o))
                               for o in program.objects]
                rc, out, cpu = step(program.link_cmd(objects, binary), suite.build, timeout)
                build_cpu += cpu
                if rc != 0:
                    status = "stillborn"
                    break
                binaries[os.path.join(suite.build, target)] = binary
        if status != "survived":
            by = label
            break
        if not binaries:
            same += 1
            continue
        if argv is None:
            cmd, cwd = [next(iter(binaries.values())), "--no-version"], suite.build
        else:
            cmd = [binaries.get(a, a) for a in argv]
        limit = min(float(limit) if limit else timeout, timeout, suite.run_limit(label, argv))
        rc, out, cpu = step(cmd, cwd, limit)
        run_cpu += cpu
        if rc is None or rc != 0:
            status, by = ("timeout" if rc is None else "killed"), label
            failed = sorted(set(re.findall(r"^TEST CASE:\s+(.*)$", out, re.M))) or \
                [out.strip().splitlines()[-1][:200] if out.strip() else f"exit status {rc}"]
            break
    shutil.rmtree(work, ignore_errors=True)
    return {"where": f"{os.path.relpath(path, ROOT)}:{i + 1}", "kind": kind,
            "before": before.strip(), "after": after.strip(), "status": status,
            "by": by, "tests": f"{tried} of {len(steps)}", "unchanged": same,
            "seconds": round(time.time() - t0, 1), "build_cpu_s": round(build_cpu, 1),
            "run_cpu_s": round(run_cpu, 1), "failed": failed}


# What a records file keeps of a result (where, kind, before and after are in its key).
RECORDED = ("key", "status", "by", "tests", "unchanged", "seconds", "build_cpu_s", "run_cpu_s",
            "failed")


def contents(path):
    with open(path, "rb") as f:
        return f.read()


def read_records(path):
    """{key: record} of a records file (blank lines skipped)."""
    out = {}
    with open(path, encoding="utf-8") as f:
        for line in f:
            if line.strip():
                r = json.loads(line)
                out[r["key"]] = r
    return out


def completed(record, site):
    """A record with the fields its key stands for (where, kind, before, after) from its site."""
    path, i, kind, before, after = site
    return dict(record, where=f"{os.path.relpath(path, ROOT)}:{i + 1}", kind=kind,
                before=before.strip(), after=after.strip())


def summary_of(path, headers, key):
    """Prints, for each header, its mutants, those recorded for its present contents and their
    statuses, the totals and every survivor; 0."""
    if not os.path.exists(path):
        print(f"mutate: no records file {path}", file=sys.stderr)
        return 2
    recorded = read_records(path)
    statuses = ("killed", "survived", "stillborn", "timeout")
    total = dict.fromkeys(statuses + ("mutants", "recorded"), 0)
    cpu = 0.0
    survivors = []
    print("| header | mutants | recorded | killed | survived | stillborn | timeout | score |")
    print("|---|---|---|---|---|---|---|---|")
    for h in headers:
        here = sites(h)
        mine = [completed(recorded[key(s)], s) for s in here if key(s) in recorded]
        n = dict.fromkeys(statuses, 0)
        for r in mine:
            n[r["status"]] += 1
            cpu += r["build_cpu_s"] + r["run_cpu_s"]
        survivors += [r for r in mine if r["status"] == "survived"]
        decided = n["killed"] + n["survived"]
        total["mutants"] += len(here)
        total["recorded"] += len(mine)
        for k in statuses:
            total[k] += n[k]
        score = f"{100.0 * n['killed'] / decided:.1f} %" if decided else "-"
        print(f"| `{os.path.relpath(h, os.path.join(ROOT, 'include', 'motionbus'))}` | "
              f"{len(here)} | {len(mine)} | " + " | ".join(str(n[k]) for k in statuses) +
              f" | {score} |")
    decided = total["killed"] + total["survived"]
    score = f"{100.0 * total['killed'] / decided:.1f} %" if decided else "-"
    print(f"| all | {total['mutants']} | {total['recorded']} | " +
          " | ".join(str(total[k]) for k in statuses) + f" | {score} |")
    per = f"{cpu / total['recorded']:.1f}" if total["recorded"] else "-"
    print(f"\nCPU {cpu:.0f} s for the {total['recorded']} recorded ({per} s a mutant)")
    for r in survivors:
        print(f"  SURVIVED {r['where']} {r['kind']}: {r['before']}  ->  {r['after']}")
    return 0


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
    ap.add_argument("--build", help="the build to mutate (all but --summary)")
    ap.add_argument("--seed", type=int, default=28)
    ap.add_argument("--count", type=int, default=300)
    ap.add_argument("--files", nargs="*", default=["include/motionbus/**/*.hpp"])
    ap.add_argument("--timeout", type=float, default=300, help="seconds per build and per run")
    ap.add_argument("--run-factor", type=float, default=10.0,
                    help="a mutant's test run times out after this many times the test's run "
                    "without a mutant (measured at the start; default 10)")
    ap.add_argument("--run-floor", type=float, default=10.0,
                    help="... but never before this many seconds (default 10)")
    ap.add_argument("--report", default=None, help="JSON report (default: BUILD/mutants.json)")
    ap.add_argument("--list", action="store_true", help="list the sample, mutate nothing")
    ap.add_argument("--site", action="append", default=[],
                    help="every mutant whose listing line contains TEXT, instead of a sample")
    ap.add_argument("--jobs", type=int, default=2,
                    help="build jobs of the unmutated build (default 2)")
    ap.add_argument("--parallel", type=int, default=1,
                    help="mutants built and run at once (default 1)")
    ap.add_argument("--all", action="store_true", help="every mutant, not a sample")
    ap.add_argument("--resume", action="store_true",
                    help="skip the mutants already in the records file (same header contents)")
    ap.add_argument("--records", default=None,
                    help="the per-mutant records, one JSON line each (default REPORT.partial)")
    ap.add_argument("--summary", action="store_true",
                    help="summarise the records file for the headers; build nothing")
    args = ap.parse_args()
    if not args.build and not (args.summary or args.list):
        ap.error("--build is required")
    headers = sorted({p for g in args.files
                      for p in glob.glob(os.path.join(ROOT, g), recursive=True)})
    everything = [s for h in headers for s in sites(h)]
    def listing(site):
        path, i, kind, before, after = site
        return f"{os.path.relpath(path, ROOT)}:{i + 1}: {kind}: {before.strip()}  ->  " \
            f"{after.strip()}"

    digest = {h: code_digest(contents(h).decode("utf-8")) for h in headers}

    def key(site):
        return f"v3 {digest[site[0]]} {code_listing(site)}"

    if args.summary:
        if not args.records:
            ap.error("--summary needs --records")
        return summary_of(args.records, headers, key)
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
    if args.records and os.path.exists(args.records) and not args.resume:
        # a records file named is never thrown away (the full run's)
        print(f"mutate: {args.records} exists: --resume to add to it", file=sys.stderr)
        return 2
    build = os.path.abspath(args.build)
    build_cmd = ["cmake", "--build", build, "-j", str(args.jobs)]
    rc, out = run(build_cmd, args.timeout * 8)
    if rc != 0:
        print("mutate: the unmutated build fails:\n" + out[-3000:], file=sys.stderr)
        return 2
    users = objects_including(build)
    if not users:
        print("mutate: no dependency log (ninja -t deps)", file=sys.stderr)
        return 2
    suite = Suite(build)
    suite.factor, suite.floor = args.run_factor, args.run_floor
    for name, argv, cwd, limit, targets in suite.tests:  # each must pass without a mutant
        t0 = time.time()
        rc, out = run(argv, float(limit) if limit else args.timeout, cwd=cwd)
        suite.seconds[name] = time.time() - t0
        if targets == ["tests/motionbus_tests"]:
            suite.seconds[None] = max(suite.seconds.get(None, 0.0), suite.seconds[name])
        if rc != 0:
            print(f"mutate: {name} fails without a mutant:\n" + out[-3000:], file=sys.stderr)
            return 2
    print(f"mutate: {len(suite.tests)} tests of {len(suite.programs)} programs "
          f"({len(suite.unit.objects) - len(suite.main)} doctest sources)", flush=True)
    work = os.path.join(build, "mutants")
    os.makedirs(work, exist_ok=True)
    # The directory of mutated headers must be searched first: a header there that cannot
    # compile must fail the build of a test source that includes it.
    probe = os.path.join(ROOT, "include", "motionbus", "core", "crc.hpp")
    probe_site = (probe, 0, "probe", "", "#error the overlay is searched first\n")
    r = mutate_one((probe_site, suite, users, args.timeout, work))
    if r["status"] != "stillborn":
        print("mutate: a mutated header is not seen by the test sources' builds",
              file=sys.stderr)
        return 2

    report = args.report or os.path.join(build, "mutants.json")
    partial = args.records or report + ".partial"  # a line a mutant as each ends: --resume
    done = {}
    if args.resume and os.path.exists(partial):
        done = read_records(partial)
    elif os.path.exists(partial):
        os.remove(partial)
    results = [completed(done[key(site)], site) for site in sample if key(site) in done]
    todo = [site for site in sample if key(site) not in done]
    if results:
        print(f"mutate: {len(results)} mutants resumed from {partial}", flush=True)
    started = time.time()
    jobs = [(site, suite, users, args.timeout, work) for site in todo]
    with concurrent.futures.ProcessPoolExecutor(max_workers=args.parallel) as pool, \
            open(partial, "a", encoding="utf-8") as log:
        futures = {pool.submit(mutate_one, job): job[0] for job in jobs}
        for future in concurrent.futures.as_completed(futures):
            r = future.result()
            r["key"] = key(futures[future])
            log.write(json.dumps({k: r[k] for k in RECORDED}) + "\n")
            log.flush()
            results.append(r)
            print(f"[{len(results)}/{len(sample)}] {r['status']:9} {r['where']} {r['kind']}: "
                  f"{r['before']}  ->  {r['after']}  ({r['tests']} tests; "
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
               "tests": "the doctest sources including the header, each alone, then the other "
                        "tests whose programs include it, until one fails"}
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
