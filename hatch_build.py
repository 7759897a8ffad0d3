"""Build faultslip's C extensions where a C compiler is available.

- faultslip.dynamics.rate_state._cycles steps a quasi-dynamic spring-block fault (see its source);
- faultslip.models.spring_chain._chain runs the spring-block chain's events and slip sub-phases.

Both are optional: without a compiler the wheel is pure Python and the same schemes run in Python, more
slowly (``faultslip methods`` and each result say which ran). setuptools' build_ext does the compiling, so
the flags are the interpreter's own on every platform. An editable install builds it beside its source.
"""

from __future__ import annotations

import sys
import sysconfig
import tempfile
from pathlib import Path

from hatchling.builders.hooks.plugin.interface import BuildHookInterface

#: each extension's module and source
EXTENSIONS = {"faultslip.dynamics.rate_state._cycles": "faultslip/dynamics/rate_state/_cycles.c",
              "faultslip.models.spring_chain._chain": "faultslip/models/spring_chain/_chain.c"}


def compile_extension(root: Path, build: Path, name: str) -> Path:
    """Compile the extension ``name`` into ``build``; return the built file."""
    from setuptools import Distribution, Extension
    from setuptools.command.build_ext import build_ext

    extension = Extension(name, [str(root / EXTENSIONS[name])],
                          extra_compile_args=["-O2"] if sys.platform != "win32" else [])
    command = build_ext(Distribution({"name": "faultslip", "ext_modules": [extension]}))
    command.build_lib, command.build_temp = str(build / "lib"), str(build / "temp")
    command.ensure_finalized()
    command.run()
    return Path(command.get_ext_fullpath(name))


class CustomBuildHook(BuildHookInterface):
    def initialize(self, version, build_data):
        if self.target_name != "wheel":
            return
        root = Path(self.root)
        for name in EXTENSIONS:
            target = name.replace(".", "/") + sysconfig.get_config_var("EXT_SUFFIX")
            try:
                built = compile_extension(root, Path(tempfile.mkdtemp(prefix="faultslip-build-")), name)
            except Exception as error:  # no compiler, no headers: the pure-Python scheme serves
                print(f"faultslip: {name} was not built ({error}); its scheme will run in Python", file=sys.stderr)
                continue
            if version == "editable":  # the editable install imports from the source tree
                (root / target).write_bytes(built.read_bytes())
                continue
            build_data["force_include"][str(built)] = target
            build_data["pure_python"] = False
            build_data["infer_tag"] = True
