"""ctest python_install: the documented install (docs/python.md) from a pristine copy of
python/ and include/, into a fresh target directory, then the pytest suite against that copy.

    install_and_test.py SOURCE_DIR WORK_DIR
"""

import os
import shutil
import subprocess
import sys


def main() -> int:
    src, work = sys.argv[1], sys.argv[2]
    shutil.rmtree(work, ignore_errors=True)
    tree = os.path.join(work, "src")
    target = os.path.join(work, "site")
    ignore = shutil.ignore_patterns("build", "*.egg-info", "__pycache__")
    shutil.copytree(os.path.join(src, "python"), os.path.join(tree, "python"), ignore=ignore)
    shutil.copytree(os.path.join(src, "include"), os.path.join(tree, "include"))
    # The documented command, with --target instead of --break-system-packages.
    cmd = ["/usr/bin/python3", "-m", "pip", "install", "--no-build-isolation", "--no-index",
           "--disable-pip-version-check", "--quiet", "--target", target, "./python"]
    print("+", " ".join(cmd), flush=True)
    subprocess.run(cmd, cwd=tree, check=True)
    env = dict(os.environ, PYTHONPATH=os.pathsep.join([target, os.path.join(src, "tests", "python")]),
               MOTIONBUS_PY_INSTALLED=target)
    return subprocess.run(["/usr/bin/python3", "-m", "pytest", "-q", "-p", "no:cacheprovider",
                           os.path.join(src, "tests", "python")], env=env, cwd=work).returncode


if __name__ == "__main__":
    sys.exit(main())
