"""Loads the dtmesh reader plugin (dtmesh_reader.py beside this file) into ParaView.

    paraview --script=/path/to/paraview/load_dtmesh.py     # the GUI, then File > Open a .dtm

In pvpython or pvbatch, the same in three lines of your script:

    import inspect; inspect.getargspec = inspect.getfullargspec
    from paraview.simple import *
    LoadPlugin("/path/to/paraview/dtmesh_reader.py", ns=globals())

Why a script and not only Tools > Manage Plugins: Debian 12's ParaView 5.11
loads Python plugins through a module that imports inspect.getargspec, which
its Python 3.11 no longer has, so every Python plugin fails to load there. The
script puts the name back (ParaView reads only .args, which getfullargspec
has too) before loading the plugin. With a ParaView whose Python plugins
load, Tools > Manage Plugins > Load New... on dtmesh_reader.py is enough.
"""
import inspect
import os

if not hasattr(inspect, "getargspec"):
    inspect.getargspec = inspect.getfullargspec

from paraview.simple import LoadPlugin  # noqa: E402

try:
    _plugin = os.path.join(os.path.dirname(os.path.abspath(__file__)), "dtmesh_reader.py")
except NameError:
    # ParaView's --script runs this file as a string, without its path: the
    # copy of the plugin installed with the package, which the reader needs
    # anyway.
    import dtmesh

    _plugin = dtmesh.paraview_plugin
LoadPlugin(_plugin, ns=globals())
