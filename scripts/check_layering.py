#!/usr/bin/env python3
"""Refuses an #include that crosses the project's layering (README "Layout").

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
    tools, tests, bench, python: anything; no library includes them.

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
# The files of codec/ that make dtm_decoder: they must not reach the hierarchy
# builder or the encoder (codec/CMakeLists.txt).
DECODER_FILES = {"format.h", "format.cpp", "layer_coder.h", "layer_coder.cpp",
                 "layer_coder_contexts.h", "layer_decoder.cpp", "decode.h", "decoder.cpp",
                 "carving_coder.h", "carving_coder.cpp", "value_coder.h", "value_coder.cpp",
                 "value_fields.h", "value_fields.cpp"}
ENCODER_HEADERS = {"codec/encode.h", "codec/expert_encode.h"}
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def allowed(folder, name, target):
    top = target.split("/")[0] if "/" in target else folder
    if folder not in LIBRARIES:
        return True
    if folder == "web" and top == "codec":
        return target.split("/")[-1] in DECODER_FILES
    if folder == "codec":
        if name in DECODER_FILES:
            return top in LIBRARIES["codec"] and target not in ENCODER_HEADERS
        return top in LIBRARIES["codec"] | {"core"}
    return top in LIBRARIES[folder]


def main():
    bad = []
    for folder in LIBRARIES:
        for path in sorted((ROOT / folder).rglob("*")):
            if path.suffix not in (".h", ".cpp") or "node_modules" in path.parts:
                continue
            for number, line in enumerate(path.read_text().splitlines(), 1):
                m = INCLUDE.match(line)
                if m and not allowed(folder, path.name, m.group(1)):
                    bad.append(f"{path.relative_to(ROOT)}:{number}: includes {m.group(1)}")
    for line in bad:
        print(line + "  (crosses the layering; see scripts/check_layering.py)")
    return 1 if bad else 0


if __name__ == "__main__":
    sys.exit(main())
