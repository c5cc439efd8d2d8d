#!/usr/bin/env python3
"""The README's C++ snippets compile and say what they print.

  readme_snippets.py README.md WORKDIR CXX STD [CXX STD ...]

Every ```cpp block of README.md is put into one program: a block with an #include is a whole
translation unit's start (its includes and declarations go first), a block that defines a
function goes to namespace scope, and any other block becomes a function of its own. In those
blocks `use(x)` records x; the first number of the comment on a `use(` line is the value the
README promises, and the program checks it. The decoder written in the README is called on a
tagged frame. The program is built with each compiler and standard given (-Wall -Wextra
-Werror) and run; any failure is the README's.
"""

import os
import re
import subprocess
import sys


def blocks(text):
    return re.findall(r"```cpp\n(.*?)```", text, re.S)


def program(snippets):
    head, scope, bodies, checks = [], [], [], []
    for k, code in enumerate(snippets):
        if "#include" in code:
            head.append(code)
            continue
        if re.search(r"^\S.*\)\s*{\s*$", code, re.M) and "decode_result<frame>" in code:
            scope.append(code)
            continue
        expected = []
        lines = []
        for line in code.splitlines():
            m = re.match(r"(.*\buse\(.*?);\s*//\s*(\d+)", line)
            if m:
                expected.append(int(m.group(2)))
            lines.append(line)
        bodies.append(f"void snippet_{k}() {{\n" + "\n".join(lines) + "\n}\n")
        checks.append((k, expected))
    out = ["#include <motionbus/motionbus.hpp>", "#include <cstdint>", "#include <cstdio>",
           "#include <vector>", ""]
    out += head
    out += ["namespace {",
            "std::vector<unsigned long long> used;",
            "template <class T> void use(const T& v) { used.push_back(static_cast<unsigned long long>(v)); }",
            "void fail(motionbus::errc) { used.push_back(~0ULL); }",
            "struct frame { std::uint8_t id = 0; };",
            "}  // namespace", ""]
    out += scope
    out += bodies
    out += ["int main() {", "  int bad = 0;"]
    for k, expected in checks:
        out.append("  used.clear();")
        out.append(f"  snippet_{k}();")
        want = ", ".join(str(e) for e in expected)
        out.append(f"  {{ const std::vector<unsigned long long> want{{{want}}};")
        out.append("    if (used.size() < want.size()) { ++bad; std::printf(\"snippet %d: %zu values used, %zu promised\\n\", "
                   f"{k}, used.size(), want.size()); }}")
        out.append("    for (std::size_t i = 0; i < want.size() && i < used.size(); ++i) if (used[i] != want[i]) { ++bad; "
                   f"std::printf(\"snippet %d: use() got %llu, the comment says %llu\\n\", {k}, used[i], want[i]); }} }}")
    if scope:
        out += ["  { const std::uint8_t tagged[] = {0x55, 0x09, 0xEE}, other[] = {0x00};",
                "    const auto r = decode_tagged(motionbus::byte_view(tagged, 3));",
                "    const auto n = decode_tagged(motionbus::byte_view(tagged, 1));",
                "    const auto f = decode_tagged(motionbus::byte_view(other, 1));",
                "    if (!r || r->id != 0x09 || r.consumed() != 2 || !n.is_incomplete() || n.needed() != 1 ||",
                "        f.error() != motionbus::errc::no_frame || f.consumed() != 1) { ++bad; std::printf(\"decode_tagged: wrong outcome\\n\"); } }"]
    out += ["  std::printf(\"%d problem(s)\\n\", bad);", "  return bad == 0 ? 0 : 1;", "}", ""]
    return "\n".join(out)


def main():
    readme, work = sys.argv[1], sys.argv[2]
    include = os.path.join(os.path.dirname(os.path.abspath(readme)), "include")
    snippets = blocks(open(readme, encoding="utf-8").read())
    if len(snippets) < 4:
        print(f"readme_snippets: {len(snippets)} C++ blocks in {readme}, expected 4 or more")
        return 1
    os.makedirs(work, exist_ok=True)
    src = os.path.join(work, "readme_snippets.cpp")
    with open(src, "w", encoding="utf-8") as f:
        f.write(program(snippets))
    status = 0
    pairs = sys.argv[3:]
    for cxx, std in zip(pairs[0::2], pairs[1::2]):
        exe = os.path.join(work, f"readme_snippets_{os.path.basename(cxx)}_{std}")
        cmd = [cxx, f"-std=c++{std}", "-O1", "-Wall", "-Wextra", "-Werror", "-I", include, src, "-o", exe]
        built = subprocess.run(cmd, capture_output=True, text=True)
        if built.returncode != 0:
            print(" ".join(cmd))
            print(built.stdout + built.stderr)
            status = 1
            continue
        ran = subprocess.run([exe], capture_output=True, text=True)
        print(f"{os.path.basename(cxx)} C++{std}: {ran.stdout.strip()}")
        if ran.returncode != 0:
            status = 1
    return status


if __name__ == "__main__":
    sys.exit(main())
