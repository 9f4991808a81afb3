#!/usr/bin/env python3
"""scripts/tidy_keys.py BUILD_DIR: a key per source file clang-tidy checks
(scripts/lint.sh), "KEY PATH", for the sources BUILD_DIR compiles.

A file's key is a hash of everything its findings can depend on in this
repository: the clang-tidy version and .clang-tidy, the file, and every
header of the project it includes, directly or through other headers
(#include "..." resolved from the repository's root, as the build does).
A file whose key is in scripts/tidy_clean.txt was found clean as it is
now, and need not be checked again.
"""
import hashlib
import json
import pathlib
import re
import subprocess
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
FOLDERS = ("common", "bitstream", "mesh", "core", "codec", "tools", "web")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"', re.M)


def sources(build):
    """The library and tool sources the build compiles (compile_commands.json)."""
    listed = subprocess.run(["git", "ls-files", "--cached", "--others", "--exclude-standard", "*.cpp"],
                            cwd=ROOT, capture_output=True, text=True, check=True).stdout.split()
    compiled = {str(pathlib.Path(e["file"]).resolve())
                for e in json.loads((pathlib.Path(build) / "compile_commands.json").read_text())}
    return sorted(p for p in listed
                  if p.split("/")[0] in FOLDERS and str((ROOT / p).resolve()) in compiled)


def closure(path, seen):
    """The project headers `path` includes, transitively."""
    for name in INCLUDE.findall((ROOT / path).read_text(errors="replace")):
        candidates = [name, str(pathlib.PurePosixPath(path).parent / name)]
        for c in candidates:
            if (ROOT / c).is_file() and c not in seen:
                seen.add(c)
                closure(c, seen)
                break
    return seen


def main():
    version = subprocess.run(["clang-tidy", "--version"], capture_output=True, text=True).stdout
    config = (ROOT / ".clang-tidy").read_bytes()
    for path in sources(sys.argv[1]):
        h = hashlib.sha256()
        h.update(version.encode())
        h.update(config)
        for part in [path] + sorted(closure(path, set())):
            h.update(part.encode() + b"\0")
            h.update((ROOT / part).read_bytes())
        print(h.hexdigest()[:32], path)


if __name__ == "__main__":
    main()
