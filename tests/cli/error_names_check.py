"""Every error name the motionbus CLI can print is in docs/cli.md's table, and the table names
nothing else.

The names are taken from the sources:
- the library's error codes: the strings of to_string() in include/motionbus/core/errc.hpp
  (`case errc::X: return "name";`);
- the CLI's own: the string literals inside `failure(...)` and `fail(...)` calls, assigned to
  an `error` variable (`error = "invalid_hex"`), and in the `{{}, ...}` results of the serial
  exchanges, in tools/motionbus/*.cpp and *.hpp.
The table's rows are the `| `name` | ... |` lines of docs/cli.md's "## Error names" section.

The check is shown to fail: it is run again with one planted `failure("...")` of a name the
docs lack, and must report that name.

Usage: error_names_check.py SOURCE_DIR. Exit 0 when the docs and the sources agree.
"""
import glob
import os
import re
import sys

NAME = re.compile(r'(?<!\[)"([a-z][a-z0-9]*(?:_[a-z0-9]+)*)"(?!\])')  # not a map key
ERRC_CASE = re.compile(r'case\s+errc::\w+:\s*return\s+"(\w+)";')
CALL = re.compile(r'\b(?:failure|fail)\(')
ASSIGNED = re.compile(r'\berror_?\s*=(?!=)\s*([^;]*);')
EXCHANGE = re.compile(r'\{\{\},\s*([^;]*)\};')
ROW = re.compile(r'^\|\s*`([a-z0-9_]+)`\s*\|', re.MULTILINE)
PLANTED = "planted_undocumented_name"


def call_arguments(text, start):
    """The text between the parenthesis that ends at `start` and its match."""
    depth = 1
    i = start
    while i < len(text) and depth > 0:
        depth += {"(": 1, ")": -1}.get(text[i], 0)
        i += 1
    return text[start:i - 1]


def without_comments(text):
    text = re.sub(r"/\*.*?\*/", "", text, flags=re.DOTALL)
    return re.sub(r"//[^\n]*", "", text)


def cli_names(texts):
    """The error names of the CLI's sources (a list of file contents)."""
    names = set()
    for text in texts:
        text = without_comments(text)
        for m in CALL.finditer(text):
            names.update(NAME.findall(call_arguments(text, m.end())))
        for pattern in (ASSIGNED, EXCHANGE):
            for m in pattern.finditer(text):
                names.update(NAME.findall(m.group(1)))
    return names


def documented_names(docs):
    """The names of the table rows in the "## Error names" section."""
    section = docs.split("\n## Error names\n", 1)[1] if "\n## Error names\n" in docs else ""
    section = section.split("\n## ", 1)[0]
    return set(ROW.findall(section))


def missing_and_stale(errc_text, texts, docs):
    names = set(ERRC_CASE.findall(errc_text)) - {"ok"}
    names |= cli_names(texts)
    documented = documented_names(docs)
    return sorted(names - documented), sorted(documented - names), names


def main():
    source = sys.argv[1]
    with open(os.path.join(source, "include", "motionbus", "core", "errc.hpp")) as f:
        errc_text = f.read()
    texts = []
    for path in sorted(glob.glob(os.path.join(source, "tools", "motionbus", "*.[ch]pp"))):
        with open(path) as f:
            texts.append(f.read())
    with open(os.path.join(source, "docs", "cli.md")) as f:
        docs = f.read()
    missing, stale, names = missing_and_stale(errc_text, texts, docs)
    status = 0
    print(f"{len(names)} error names found in the sources")
    if missing:
        print("FAIL not in docs/cli.md's table of error names: " + ", ".join(missing))
        status = 1
    if stale:
        print("FAIL in docs/cli.md's table, but printed nowhere: " + ", ".join(stale))
        status = 1
    # the check can fail: a planted name the docs lack is reported
    planted, _, _ = missing_and_stale(
        errc_text, texts + [f'return cli::finish(cli::outcome::failure("{PLANTED}"));'], docs)
    if PLANTED not in planted:
        print("FAIL the check did not report a planted undocumented name")
        status = 1
    if status == 0:
        print("ok   every error name the CLI prints is documented")
    return status


if __name__ == "__main__":
    sys.exit(main())
