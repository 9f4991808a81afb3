#!/usr/bin/env python3
"""Refuses an #include that crosses the project's layering (docs/ARCHITECTURE.md §2).

Each library folder may include only the folders below it:

    common                      <- everything
    bitstream  -> common
    mesh       -> common
    core       -> common, mesh              (the hierarchy builder)
    codec      -> common, bitstream, mesh   (the decoder's files)
                  + core                    (the encoder's files only)
    web        -> common, bitstream, mesh, codec's decoder files
                  (the viewer: it is built for WebAssembly, where the
                  hierarchy builder and the encoder do not exist)
    tools, tests, bench, research, python: anything; no library includes them.

Which files of codec/ are the encoder's is read from the tree, not from a
list: codec/blocks/ and every file whose name says encode (encode.h,
expert_encode.cpp, sections/value_encoder.cpp, ...). The rest are the
decoder's, and codec/CMakeLists.txt must build dtm_decoder from them alone
and dtm_encoder from the others: that is checked too.

Run by ctest (test 'layering') and so by CI: an include across a forbidden
arrow fails the suite, not just a reviewer's eye. Exit status 1 lists every
offending line.
"""
import pathlib
import re
import sys

ROOT = pathlib.Path(__file__).resolve().parent.parent
LIBRARIES = {
    "common": {"common"},
    "bitstream": {"common", "bitstream"},
    "mesh": {"common", "mesh"},
    "core": {"common", "mesh", "core"},
    "codec": {"common", "bitstream", "mesh", "codec"},
    "web": {"common", "bitstream", "mesh", "codec", "web"},
}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def is_encoder(codec_path):
    """codec_path: a path inside codec/, e.g. 'blocks/block_runs.h'."""
    return codec_path.startswith("blocks/") or "encode" in codec_path.split("/")[-1]


def allowed(folder, relative, target):
    top = target.split("/")[0] if "/" in target else folder
    if folder not in LIBRARIES:
        return True
    if top == "codec" and folder in ("codec", "web"):
        inside = target[len("codec/"):]
        if is_encoder(inside):
            return folder == "codec" and is_encoder(relative)
        return True
    if folder == "codec" and top == "core":
        return is_encoder(relative)
    return top in LIBRARIES[folder]


def check_includes():
    bad = []
    for folder in LIBRARIES:
        for path in sorted((ROOT / folder).rglob("*")):
            if path.suffix not in (".h", ".cpp") or "node_modules" in path.parts:
                continue
            relative = path.relative_to(ROOT / folder).as_posix()
            for number, line in enumerate(path.read_text().splitlines(), 1):
                m = INCLUDE.match(line)
                if m and not allowed(folder, relative, m.group(1)):
                    bad.append(f"{path.relative_to(ROOT)}:{number}: includes {m.group(1)}"
                               "  (crosses the layering; see scripts/check_layering.py)")
    return bad


def check_libraries():
    """dtm_decoder from the decoder's files, dtm_encoder from the encoder's, each file once."""
    text = (ROOT / "codec" / "CMakeLists.txt").read_text()
    sources = {}
    for name in ("dtm_decoder", "dtm_encoder"):
        m = re.search(r"add_library\(%s\s+([^)]*)\)" % name, text)
        sources[name] = m.group(1).split() if m else []
    bad = []
    for name, files in sources.items():
        for f in files:
            if is_encoder(f) != (name == "dtm_encoder"):
                bad.append(f"codec/CMakeLists.txt: {name} builds {f}, "
                           f"{'an encoder' if is_encoder(f) else 'a decoder'} file")
    listed = sources["dtm_decoder"] + sources["dtm_encoder"]
    for path in sorted((ROOT / "codec").rglob("*.cpp")):
        f = path.relative_to(ROOT / "codec").as_posix()
        if listed.count(f) != 1:
            bad.append(f"codec/CMakeLists.txt: {f} is built {listed.count(f)} times (once is right)")
    return bad


def main():
    bad = check_includes() + check_libraries()
    for line in bad:
        print(line)
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
