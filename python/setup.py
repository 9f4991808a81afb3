"""Builds dtmesh's extension module with the project's CMake build.

The C++ library is built once per checkout in python/build/cmake (or in
$DTMESH_CMAKE_BUILD), with position-independent code and without the tests
and benchmarks, and only the target _dtmesh is asked for: a second
`pip install` rebuilds what changed, nothing else.

$DTMESH_PREBUILT_MODULE, the path of a _dtmesh module a build of the project
already made (the test suite's build makes one beside the tools), is
installed as it is instead: the suite does not build the library twice.
"""
import os
import pathlib
import subprocess
import sys

from setuptools import Extension, setup
from setuptools.command.build_ext import build_ext
from setuptools.command.build_py import build_py

HERE = pathlib.Path(__file__).resolve().parent
ROOT = HERE.parent


class CMakeExtension(Extension):
    def __init__(self, name):
        super().__init__(name, sources=[])


class CMakeBuild(build_ext):
    def build_extension(self, ext):
        target = pathlib.Path(self.get_ext_fullpath(ext.name)).resolve()
        prebuilt = os.environ.get("DTMESH_PREBUILT_MODULE")
        if prebuilt:
            target.parent.mkdir(parents=True, exist_ok=True)
            self.copy_file(prebuilt, str(target))
            return
        build = pathlib.Path(os.environ.get("DTMESH_CMAKE_BUILD", HERE / "build" / "cmake"))
        configure = [
            "cmake", "-S", str(ROOT), "-B", str(build),
            "-DCMAKE_BUILD_TYPE=Release",
            "-DDTM_PYTHON=ON", "-DDTM_BUILD_TESTS=OFF", "-DDTM_BUILD_BENCH=OFF", "-DDTM_WEB_TESTS=OFF",
            f"-DPython_EXECUTABLE={sys.executable}",
            f"-DCMAKE_LIBRARY_OUTPUT_DIRECTORY={target.parent}",
        ]
        try:
            import pybind11

            configure.append(f"-Dpybind11_DIR={pybind11.get_cmake_dir()}")
        except ImportError:
            pass  # CMake looks for pybind11's package itself (Debian's pybind11-dev)
        subprocess.run(configure, check=True, stdout=subprocess.DEVNULL)
        jobs = str(os.cpu_count() or 2)
        subprocess.run(["cmake", "--build", str(build), "--target", "_dtmesh", "-j", jobs], check=True)
        if not target.exists():
            raise RuntimeError(f"the build did not make {target}")


class WithParaViewReader(build_py):
    """Ships the ParaView reader (../paraview/dtmesh_reader.py) in the package:
    dtmesh.paraview_plugin names it, for Tools > Manage Plugins and
    paraview/load_dtmesh.py."""

    def run(self):
        super().run()
        if not self.dry_run:
            target = pathlib.Path(self.build_lib) / "dtmesh" / "paraview_reader.py"
            self.copy_file(str(ROOT / "paraview" / "dtmesh_reader.py"), str(target))


setup(ext_modules=[CMakeExtension("dtmesh._dtmesh")],
      cmdclass={"build_ext": CMakeBuild, "build_py": WithParaViewReader})
