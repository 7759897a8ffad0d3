"""The package's layers point down only, with no import circles (docs/architecture.md).

Every import statement in faultslip/ is read with ``ast``, including imports inside functions:

* a module may import from its own subpackage, or from a lower layer;
* imports at module level form no circle;
* an import inside a function is only for a heavy optional dependency (xarray, matplotlib,
  scipy, obspy, dask, netCDF4, ...) and says so in a comment, or for a platform module;
* the command line starts without numpy, pint or the physics: ``--help`` imports none of them.
"""

import ast
import re
import subprocess
import sys
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[2] / "faultslip"
#: Lowest first. Studies, lab and evaluation share a layer but may not import each other.
LAYERS = {"core": 0, "io": 1, "contract": 1.5, "friction": 2, "dynamics": 3, "fault": 4, "studies": 5, "lab": 5, "evaluation": 5,
          "plots": 6, "models": 7, "hazard": 7.2, "cli": 8, "apps": 7.5}
# hazard is a facade (faultslip.api's "hazard" topic): a package with an __init__ only, over studies, fault and
# evaluation
HEAVY = {"xarray", "matplotlib", "scipy", "obspy", "dask", "distributed", "netCDF4", "mpmath", "psutil", "tqdm", "pint", "h5py", "zarr", "numcodecs", "numba", "bokeh", "selenium", "PIL",
         "mpl_toolkits", "openpyxl", "dask_jobqueue", "rocket_fft", "llvmlite", "fdhpy", "cutde"}  # basemap (mpl_toolkits),
# openpyxl, dask-jobqueue, rocket-fft, fdhpy: the optional maps, xlsx, dask (--scheduler slurm), fast (numba's FFTs)
# and fdh (the field's displacement models) extras; llvmlite: numba's own, for the compiled step's intrinsics;
# cutde: compiled dislocations, loaded only where a 3-D fault is built
PLATFORM = {"fcntl", "multiprocessing", "webbrowser"}


def _module_name(path: Path) -> str:
    parts = path.relative_to(PACKAGE.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


#: Top-level modules that are the program, not the core: ``python -m faultslip`` runs the command line, as
#: faultslip/cli/__main__.py does, so it sits with cli at the top.
PROGRAM = {"faultslip.__main__": "cli"}


def _room(module: str) -> str:
    """The layer a module belongs to: its subpackage, or 'core' for faultslip's top-level modules."""
    if module in PROGRAM:
        return PROGRAM[module]
    parts = module.split(".")
    return parts[1] if len(parts) > 2 or (len(parts) == 2 and parts[1] in LAYERS) else "core"


def _imports(path: Path):
    """(target module, line, inside a function, source line) for every faultslip or third-party import."""
    text = path.read_text(encoding="utf-8")
    tree = ast.parse(text)
    lines = text.splitlines()
    inside = set()
    for node in ast.walk(tree):
        if isinstance(node, (ast.FunctionDef, ast.AsyncFunctionDef)):
            inside.update(id(sub) for sub in ast.walk(node) if isinstance(sub, (ast.Import, ast.ImportFrom)))
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            for alias in node.names:
                yield alias.name, node.lineno, id(node) in inside, lines[node.lineno - 1]
        elif isinstance(node, ast.ImportFrom) and node.module:
            assert node.level == 0, f"{path}:{node.lineno}: use absolute imports (faultslip.x.y)"
            if node.module == "faultslip":  # from faultslip import ranges / __version__
                for alias in node.names:
                    target = f"faultslip.{alias.name}" if alias.name != "__version__" else "faultslip"
                    yield target, node.lineno, id(node) in inside, lines[node.lineno - 1]
            else:
                for alias in node.names:
                    candidate = f"{node.module}.{alias.name}"
                    is_module = (PACKAGE.parent / (candidate.replace(".", "/") + ".py")).exists() or \
                        (PACKAGE.parent / candidate.replace(".", "/")).is_dir()
                    yield (candidate if is_module else node.module), node.lineno, id(node) in inside, \
                        lines[node.lineno - 1]


MODULES = {_module_name(p): p for p in sorted(PACKAGE.rglob("*.py"))}


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_point_down_only(module):
    source_room = _room(module)
    for target, line, _, _ in _imports(MODULES[module]):
        if not target.startswith("faultslip.") or target == "faultslip":
            continue
        target_room = _room(target)
        if target_room == source_room:
            continue
        assert LAYERS[target_room] < LAYERS[source_room], (
            f"{module}:{line} imports {target}: {target_room} is not below {source_room} (docs/architecture.md)")


@pytest.mark.parametrize("module", sorted(MODULES))
def test_imports_inside_functions_are_only_for_heavy_optional_dependencies(module):
    for target, line, inside, text in _imports(MODULES[module]):
        if not inside:
            continue
        top = target.split(".")[0]
        if top in PLATFORM or (module == "faultslip" and top == "importlib"):
            continue
        assert top in HEAVY, f"{module}:{line} hides 'import {target}' in a function; import it at module level"
        assert "#" in text and "heavy" in text.split("#", 1)[1], f"{module}:{line}: say why the import is here"


def test_no_import_circles():
    graph = {module: set() for module in MODULES}
    for module, path in MODULES.items():
        for target, _, inside, _ in _imports(path):
            if not inside and target in MODULES and target != module:
                graph[module].add(target)
    state, stack = {}, []

    def visit(node):
        state[node] = "open"
        stack.append(node)
        for nxt in sorted(graph[node]):
            if state.get(nxt) == "open":
                cycle = stack[stack.index(nxt):] + [nxt]
                raise AssertionError("import circle: " + " -> ".join(cycle))
            if nxt not in state:
                visit(nxt)
        stack.pop()
        state[node] = "done"

    for module in sorted(graph):
        if module not in state:
            visit(module)


def test_the_command_line_starts_without_the_physics():
    code = ("import sys; from faultslip.cli.main import build_parser; build_parser(); "
            "heavy = sorted(m for m in ('numpy', 'pint', 'scipy', 'xarray', 'matplotlib', 'faultslip.units') "
            "if m in sys.modules); print(','.join(heavy))")
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout.strip()
    assert loaded == "", f"building the parser loaded {loaded}"


def test_a_cycle_run_loads_only_what_it_needs():
    """faultslip rate-state cycles, often one short process (benchmarks/spring_block_qdyn.py times it whole
    against QDYN), builds only its own options and loads no other family, no figures and no scipy: measured,
    its imports went from 340 to about 90 ms beside numpy's. The first run in an install loads pint once, to
    memoise its unit factors on disk (faultslip.units), as CI's fresh environment showed: that run goes first."""
    root = Path(__file__).resolve().parents[2]
    subprocess.run([sys.executable, "-m", "faultslip.cli", "rate-state", "cycles", "configs/rsf_block_bp1.toml",
                    "--cycles", "1", "--json"], capture_output=True, check=True, cwd=root)
    code = ("import io, sys, contextlib; from faultslip.cli.main import main\n"
            "with contextlib.redirect_stdout(io.StringIO()):\n"
            "    main(['rate-state', 'cycles', 'configs/rsf_block_bp1.toml', '--cycles', '1', '--json'])\n"
            "print(','.join(sorted(m for m in sys.modules if m in ('scipy', 'xarray', 'matplotlib', 'pint', 'netCDF4', "
            "'numba', 'dask', 'h5py', 'faultslip.fault.scaling', 'faultslip.dynamics.methods', 'faultslip.cli.common', "
            "'faultslip.models.rate_state_slider.family', 'faultslip.models.fault_2d.family', 'faultslip.fault.scene'))))")
    loaded = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                            cwd=root).stdout.strip()
    assert loaded == "", f"a cycle run loaded {loaded}"


def test_a_netcdf_sweep_never_imports_dask_array(tmp_path):
    """dask.array is for lazy studies and clusters: importing it costs about 0.4 s that a plain sweep never needs.

    (pint imports dask's core, not dask.array, when dask is installed; that part is pint's.)
    """
    study = tmp_path / "study.toml"
    study.write_text('[study]\nbase = "san_andreas_1906.toml"\n[sweep]\nslip_rate = ["5 mm/yr", "50 mm/yr"]\n'
                     'lithology = ["granodiorite", "pyrite_dry"]\n')
    code = ("import sys; from faultslip.cli.main import main; "
            f"main(['sweep', {str(study)!r}, '-o', {str(tmp_path / 'out.nc')!r}, '--json']); "
            "print('dask.array' if 'dask.array' in sys.modules else 'no dask.array', file=sys.stderr)")
    result = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True)
    assert result.stderr.strip().splitlines()[-1] == "no dask.array", result.stderr


def test_the_folder_listing_is_the_architecture():
    rooms = sorted(p.name for p in PACKAGE.iterdir() if p.is_dir() and (p / "__init__.py").exists())
    assert rooms == sorted(name for name in LAYERS if name != "core")
    loose = sorted(p.stem for p in PACKAGE.glob("*.py") if p.stem != "__init__")
    assert loose == ["__main__", "api", "constants", "datasets", "errors", "intervals", "ranges", "units"], loose


#: Names that tell scene kinds apart by their contents: only faultslip.contract.registry may use them.
SNIFFERS = {"is_asperity_scene", "is_nanoscale_scene", "is_vibration_scene", "is_rough_scene", "has_friction_law",
            "scene_document"}


@pytest.mark.parametrize("module", sorted(m for m in MODULES if m.startswith("faultslip.cli")))
def test_the_command_line_holds_no_scene_kind_dispatch(module):
    """run and simulate ask faultslip.models for a scene's family; no if-chain over kinds lives in cli/."""
    tree = ast.parse(MODULES[module].read_text(encoding="utf-8"))
    used = {node.id for node in ast.walk(tree) if isinstance(node, ast.Name)} | \
           {alias.name for node in ast.walk(tree) if isinstance(node, ast.ImportFrom) for alias in node.names}
    assert not used & SNIFFERS, f"{module} tells scene kinds apart itself ({sorted(used & SNIFFERS)}); ask faultslip.models"


EXAMPLES = sorted((PACKAGE.parent / "examples").glob("*.py"))


@pytest.mark.parametrize("example", EXAMPLES, ids=lambda p: p.name)
def test_gallery_examples_use_the_public_api_only(example):
    """Whatever the gallery shows, a user can import: the top level's names and each topic's (faultslip.api)."""
    import faultslip
    from faultslip import api

    public = {"faultslip": set(faultslip.__all__)} | {f"faultslip.{topic}": set(names)
                                                      for topic, names in api.TOPICS.items()}
    tree = ast.parse(example.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("faultslip"):
            assert node.module in public, (
                f"{example.name}:{node.lineno} imports the internal module {node.module}; export what it needs "
                "through faultslip/api.py")
            private = [a.name for a in node.names if a.name not in public[node.module]]
            assert not private, f"{example.name}:{node.lineno}: {private} are not public names of {node.module}"
        if isinstance(node, ast.Attribute) and isinstance(node.value, ast.Name) and node.value.id == "faultslip":
            assert node.attr in faultslip.__all__ or node.attr == "__version__", (
                f"{example.name}:{node.lineno}: faultslip.{node.attr} is not a top-level name")


def test_the_api_reference_lists_every_public_name():
    from faultslip import api

    text = (PACKAGE.parent / "docs" / "api.rst").read_text(encoding="utf-8")
    missing = [name for name in api.public_names() if f"``{name}``" not in text]
    assert not missing, f"docs/api.rst does not list {missing}"
    check = subprocess.run([sys.executable, str(PACKAGE.parent / "docs" / "api_reference.py"), "--check"],
                           capture_output=True, text=True)
    assert check.returncode == 0, check.stderr


def test_the_top_level_is_small_and_every_topic_name_resolves():
    """The top level holds the command line's five verbs, Result, the errors, the units and the topics (issue 70);
    every topic's name resolves to an object, and each is listed once."""
    import faultslip
    from faultslip import api

    assert {"run", "simulate", "sweep", "fit", "map", "Result"} <= set(faultslip.__all__)
    assert len(faultslip.__all__) <= 20, faultslip.__all__
    for name, where in api.public_names().items():
        assert api.resolve(where) is not None, name
    homes = {}
    for topic, names in api.TOPICS.items():
        assert set(names) <= set(getattr(faultslip, topic).__all__) <= set(dir(getattr(faultslip, topic)))
        for name in names:
            homes.setdefault(name, []).append(topic)
    assert {name: topics for name, topics in homes.items() if len(topics) > 1} == {}


def test_an_old_flat_name_still_works_for_a_release_and_says_where_it_went():
    import faultslip
    from faultslip import api

    for old, (new, where) in api.MOVED.items():
        with pytest.warns(FutureWarning, match=new.replace(".", r"\.")):
            assert getattr(faultslip, old) is api.resolve(where), old
    with pytest.raises(AttributeError):
        faultslip.no_such_name  # noqa: B018


#: The numerics in dynamics/ that several families and applications share: each imports only itself, the shared
#: machinery and, for seed 002's averaging built on it, the spring-slider. The method hierarchy (methods, kernel)
#: sits above them. A family's numerics that nothing else uses live in its own folder (models/<family>/).
DYNAMICS_FAMILIES = {"spring_slider": set(), "rate_state": set(), "vibration": {"spring_slider"}}
DYNAMICS_HUB = {"methods", "kernel"}


def test_dynamics_is_families_and_shared_machinery_not_one_room():
    room = PACKAGE / "dynamics"
    top_modules = sorted(p.stem for p in room.glob("*.py") if p.stem != "__init__")
    assert set(top_modules) <= set(DYNAMICS_FAMILIES) | DYNAMICS_HUB, (
        f"dynamics/ holds {top_modules}: a new family is a module or subpackage declared in DYNAMICS_FAMILIES")
    packages = sorted(p.name for p in room.iterdir() if p.is_dir() and (p / "__init__.py").exists())
    assert set(packages) <= set(DYNAMICS_FAMILIES) | {"shared"}
    for module, path in MODULES.items():
        parts = module.split(".")
        if len(parts) < 3 or parts[1] != "dynamics" or parts[2] not in DYNAMICS_FAMILIES | {"shared": 0}:
            continue
        family = parts[2]
        allowed = {family, "shared"} | DYNAMICS_FAMILIES.get(family, set())
        for target, line, _, _ in _imports(path):
            tparts = target.split(".")
            if target.startswith("faultslip.dynamics.") and len(tparts) > 2:
                assert tparts[2] in allowed, (
                    f"{module}:{line} imports {target}: a family uses only itself and dynamics.shared")


FAMILY_FOLDERS = sorted(p.name for p in (PACKAGE / "models").iterdir() if (p / "family.py").exists())
#: A family built on another's machinery, declared: the 3-D fault takes the 2-D fault's force balance, stepping,
#: records, checkpoints and sequence classification (issue 72: the 3-D rung re-implements none of them).
FAMILY_BUILDS_ON = {"fault_3d": {"fault_2d"}}


def test_a_family_is_one_folder_and_no_module_outside_it_imports_it():
    """Families as vertical slices (issue 40): each registered family is ``models/<name>/`` with its declaration in
    ``family.py``; only its own folder imports it. Everything else reaches a family through the contract
    (``faultslip.contract.load``, ``cells_of``, ``Family.refine``) or the public names of ``import faultslip``."""
    from faultslip import contract

    declared = {name: declaration.module for name, declaration in contract.DECLARATIONS.items()}
    assert declared == {name: f"faultslip.models.{name}.family" for name in FAMILY_FOLDERS}, declared
    for module, path in MODULES.items():
        parts = module.split(".")
        own = parts[2] if len(parts) > 2 and parts[1] == "models" and parts[2] in FAMILY_FOLDERS else None
        for target, line, _, _ in _imports(path):
            tparts = target.split(".")
            if len(tparts) > 2 and tparts[:2] == ["faultslip", "models"] and tparts[2] in FAMILY_FOLDERS:
                assert tparts[2] == own or tparts[2] in FAMILY_BUILDS_ON.get(own, ()), (
                    f"{module}:{line} imports {target}: only models/{tparts[2]}/ may; go through the contract "
                    "or the public API (import faultslip)")


def test_the_test_family_is_one_folder_too():
    """The test family is a folder like every family's, declared by one line in tests/capabilities/contract/test_families.py."""
    folder = PACKAGE.parent / "tests" / "families" / "constant_friction"
    assert sorted(p.name for p in folder.glob("*.py")) == ["__init__.py", "family.py", "figures.py", "scene.py"]
    for path in folder.glob("*.py"):
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
            if isinstance(node, ast.ImportFrom) and node.module and node.module.startswith("faultslip.models."):
                raise AssertionError(f"{path.name}:{node.lineno} imports {node.module}: a family needs only the contract")


#: Calls that open, save, load, map or rename a file: outside io/, none may stand (the door of issue 41: the
#: gate reads, bounded and in one sentence; the guard writes, locked, without following links, atomically).
FILE_CALLS = {"open", "os.open", "os.fdopen", "os.replace", "os.rename", "os.renames", "os.link", "os.symlink",
              "shutil.move", "shutil.copy", "shutil.copyfile", "shutil.copy2", "shutil.copytree", "np.save", "np.savez",
              "np.savez_compressed", "np.load", "np.memmap", "np.fromfile", "np.savetxt", "np.loadtxt", "np.genfromtxt",
              "netCDF4.Dataset", "h5py.File", "xr.open_dataset", "xr.open_zarr", "xr.open_mfdataset",
              "xr.load_dataset", "xarray.open_dataset", "obspy.read", "read_events", "zarr.open", "zarr.open_group",
              "tempfile.mkstemp", "tempfile.NamedTemporaryFile", "pickle.load", "pickle.dump"}
#: Methods that do the same on a Path, an array, a Dataset or a figure (whatever the receiver is called),
#: unless called on the gate itself (gate.read_text is the door).
FILE_METHODS = {"write_text", "write_bytes", "read_text", "read_bytes", "tofile", "to_netcdf", "to_zarr", "savefig",
                "symlink_to", "hardlink_to", "memmap"}
#: The only exceptions, each with its reason: (module, function) -> why.
FILE_CALL_EXCEPTIONS = {
    ("faultslip.units", "_read_memo_file"): "core, below io/: its own per-environment cache of pint's factors, no user "
                                           "path; opened O_NOFOLLOW, non-blocking, regular files only, bounded",
    ("faultslip.units", "_remember"): "the same cache, written atomically; a failed write costs only a lookup",
    ("faultslip.units", "_memo_lock"): "the same cache's lock file beside it, opened O_NOFOLLOW; no user path",
    ("faultslip.cli.main", "main"): "os.devnull over a closed stdout (a broken pipe), no user path",
}


def _call_name(node):
    if isinstance(node, ast.Name):
        return node.id
    if isinstance(node, ast.Attribute):
        inner = _call_name(node.value)
        return f"{inner}.{node.attr}" if inner else None
    return None


def _file_calls(path: Path):
    """(line, call, enclosing function) for every file call in ``path``."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    owner = {}
    # the innermost enclosing function wins: walk functions outermost first, later (inner) ones overwrite
    functions = [n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))]
    for function in functions:
        for sub in ast.walk(function):
            owner[id(sub)] = function.name
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        name = _call_name(node.func)
        method = node.func.attr if isinstance(node.func, ast.Attribute) else None
        receiver = _call_name(node.func.value) if isinstance(node.func, ast.Attribute) else None
        if name in FILE_CALLS or (method in FILE_METHODS and receiver != "gate"):
            yield node.lineno, name or method, owner.get(id(node), "<module>")


@pytest.mark.parametrize("module", sorted(m for m in MODULES if not m.startswith("faultslip.io")))
def test_every_file_is_opened_through_the_door(module):
    """No open, save, load, memmap or rename of a file outside io/: new code reads through the gate
    (faultslip.io.gate, io.resources, io.records) and writes through the guard (io.atomic, io.records)."""
    offenders = [f"{module}:{line} calls {call}" for line, call, function in _file_calls(MODULES[module])
                 if (module, function) not in FILE_CALL_EXCEPTIONS]
    assert not offenders, ("files are opened outside io/: " + "; ".join(offenders)
                           + " (read through faultslip.io.gate, write through faultslip.io.atomic)")


def test_the_door_check_sees_what_it_must():
    """The scanner finds each kind of call it lists (a check that cannot fail is no check)."""
    import textwrap

    sample = PACKAGE.parent / "tests" / "_door_sample.py"
    sample.write_text(textwrap.dedent("""
        def f(path, data, figure, dataset):
            open(path)
            np.load(path)
            np.memmap(path)
            os.replace(path, path)
            path.write_text("x")
            figure.savefig(path)
            dataset.to_netcdf(path)
            xr.open_dataset(path)
            gate.read_text(path, "x")
    """))
    try:
        found = {call for _, call, _ in _file_calls(sample)}
    finally:
        sample.unlink()
    assert found == {"open", "np.load", "np.memmap", "os.replace", "path.write_text", "figure.savefig",
                     "dataset.to_netcdf", "xr.open_dataset"}


#: Where a netCDF file may be created, each with its reason: every other writer goes through faultslip.io.netcdf,
#: whose files are sealed with a checksum that every read checks (faultslip.io.netcdf.seal).
NETCDF_CREATORS = {
    "faultslip.io.netcdf": "write_dataset and create_chunked, whose callers seal what they write",
    "faultslip.io.bundle": "netCDF bytes inside a fit bundle, whose manifest holds every member's SHA-256",
}


def _netcdf_creations(path: Path):
    """(line, what) for each call in ``path`` that creates a netCDF file: ``to_netcdf``, a ``netCDF4.Dataset``
    opened to write (``"w"``, ``"x"``), and ``create_chunked`` (which must be sealed in the same module)."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    calls = [node for node in ast.walk(tree) if isinstance(node, ast.Call)]
    names = {_call_name(node.func) for node in calls}
    for node in calls:
        name = _call_name(node.func)
        method = node.func.attr if isinstance(node.func, ast.Attribute) else None
        modes = [a.value for a in node.args[1:2] + [k.value for k in node.keywords if k.arg == "mode"]
                 if isinstance(a, ast.Constant)]
        if method == "to_netcdf" or (name == "netCDF4.Dataset" and any(m in ("w", "x") for m in modes)):
            yield node.lineno, name or method
        elif name == "create_chunked" and "seal" not in names:
            yield node.lineno, "create_chunked with no seal"


@pytest.mark.parametrize("module", sorted(MODULES))
def test_every_netcdf_file_is_written_sealed(module):
    """A netCDF file is created only where it is sealed with its checksum (the writer guard of every netCDF file)."""
    found = [f"{module}:{line} calls {what}" for line, what in _netcdf_creations(MODULES[module])
             if module not in NETCDF_CREATORS or what == "create_chunked with no seal"]
    assert not found, "a netCDF file written outside faultslip.io.netcdf, or left unsealed: " + "; ".join(found)


def test_the_netcdf_writer_check_sees_what_it_must(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text("def f(dataset, path):\n    dataset.to_netcdf(path)\n    netCDF4.Dataset(path, 'w')\n"
                      "    netCDF4.Dataset(path, mode='x')\n    netCDF4.Dataset(path)\n    create_chunked(path)\n")
    assert [what for _, what in _netcdf_creations(sample)] == ["dataset.to_netcdf", "netCDF4.Dataset",
                                                               "netCDF4.Dataset", "create_chunked with no seal"]


def _bundled_table_reads(path: Path):
    """(line, producer) for each ``read_bundled_table(name, label, producer)`` call in ``path``, and (line, None)
    for a JSON read of ``bundled_dir("data")`` that goes around it."""
    tree = ast.parse(path.read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if not isinstance(node, ast.Call):
            continue
        name = _call_name(node.func)
        if name == "read_bundled_table" and len(node.args) >= 3 and isinstance(node.args[2], ast.Constant):
            yield node.lineno, node.args[2].value
        elif name in ("gate.read_json", "read_json", "json.loads") and "bundled_dir" in ast.unparse(node):
            yield node.lineno, None


@pytest.mark.parametrize("module", sorted(MODULES))
def test_every_bundled_table_is_read_against_the_checksum_its_benchmark_sealed(module):
    """A table in data/ is read only through read_bundled_table, which checks its checksum, and the benchmark it
    names as the table's producer writes it with write_bundled_table, which seals it."""
    problems = []
    for line, producer in _bundled_table_reads(MODULES[module]):
        if producer is None:
            problems.append(f"{module}:{line} reads a bundled JSON table around read_bundled_table")
            continue
        script = PACKAGE.parent / producer
        if not script.is_file() or "write_bundled_table(" not in script.read_text(encoding="utf-8"):
            problems.append(f"{module}:{line} names {producer}, which does not write it with write_bundled_table")
    assert not problems, "; ".join(problems)


def test_the_bundled_table_check_sees_what_it_must(tmp_path):
    sample = tmp_path / "sample.py"
    sample.write_text("def f():\n    read_bundled_table('a.json', 'a', 'benchmarks/a.py')\n"
                      "    gate.read_json(bundled_dir('data') / 'b.json', 'b')\n    read_bundled_table(name, label, producer)\n")
    assert list(_bundled_table_reads(sample)) == [(2, "benchmarks/a.py"), (3, None)]


def test_every_public_function_documents_its_parameters_and_returns():
    """numpydoc sections on every name of ``import faultslip``, as MetPy's calc has (issue 40, item 8): a function
    with parameters has a Parameters section, every function a Returns section, a class Parameters or
    Attributes; their units are in the sections' text."""
    import inspect


    from faultslip import api

    missing = []
    for name, where in api.public_names().items():
        obj = api.resolve(where)
        doc = inspect.getdoc(obj) or ""
        if inspect.isclass(obj):
            if "Parameters\n---" not in doc and "Attributes\n---" not in doc:
                missing.append(name)
        elif inspect.isfunction(obj):
            takes = [p for p in inspect.signature(obj).parameters.values() if p.name not in ("self", "cls")]
            if (takes and "Parameters\n---" not in doc) or "Returns\n---" not in doc:
                missing.append(name)
    assert not missing, f"public names without numpydoc Parameters / Returns: {missing}"


def test_the_public_api_names_each_module_once():
    """A key listed twice in faultslip/api.py's tables silently drops the first (a dict literal keeps the last
    key): read_step_record vanished that way once."""
    import ast
    from collections import Counter

    tree = ast.parse((PACKAGE / "api.py").read_text(encoding="utf-8"))
    for node in ast.walk(tree):
        if isinstance(node, ast.Dict):
            keys = [key.value for key in node.keys if isinstance(key, ast.Constant)]
            twice = sorted(key for key, count in Counter(keys).items() if count > 1)
            assert not twice, f"faultslip/api.py lists {twice} twice"


def test_cores_are_counted_in_one_place():
    """A process's cores are :func:`faultslip.io.processes.usable_cores`, its CPU affinity: a process held to
    some cores (taskset, a container's or a SLURM job's cpuset) must not start a worker or a thread for each of
    the machine's. No other function counts them."""
    counters = {"os.cpu_count", "multiprocessing.cpu_count", "psutil.cpu_count", "cpu_count"}
    found = []
    for module, path in MODULES.items():
        tree = ast.parse(path.read_text(encoding="utf-8"))
        owner = {}
        for function in (n for n in ast.walk(tree) if isinstance(n, (ast.FunctionDef, ast.AsyncFunctionDef))):
            owner.update((id(sub), function.name) for sub in ast.walk(function))
        found += [(module, owner.get(id(node), "<module>")) for node in ast.walk(tree)
                  if isinstance(node, ast.Call) and _call_name(node.func) in counters]
    assert found == [("faultslip.io.processes", "usable_cores")], found


def _hand_checked_tolerances(tree) -> list[str]:
    """Comparisons of a tolerance with 0 or 1 (``0 < tolerance < 1``, ``tolerance > 0``; a name holding
    "tolerance"): a tolerance checked by hand rather than by :func:`faultslip.ranges.check_tolerance`."""
    found = []
    for node in ast.walk(tree):
        if not isinstance(node, ast.Compare):
            continue
        operands = [node.left, *node.comparators]
        names = [o.id if isinstance(o, ast.Name) else o.attr if isinstance(o, ast.Attribute) else "" for o in operands]
        bounds = [o for o in operands if isinstance(o, ast.Constant) and not isinstance(o.value, bool)
                  and o.value in (0, 1)]
        if bounds and any("tolerance" in name for name in names):
            found.append(f"line {node.lineno}")
    return found


def test_a_tolerance_is_checked_in_one_place():
    """Every tolerance a user gives (an option, a keyword, a scene's or a study's key) is read by
    :func:`faultslip.ranges.check_tolerance`: "0.1", "1e-3" and "10 %" alike, the rest in one sentence. Seven
    copies had refused a notebook's tolerance="0.1" that the command took."""
    found = []
    for module, path in MODULES.items():
        if module == "faultslip.ranges":
            continue
        found += [f"{module} {where}" for where in _hand_checked_tolerances(ast.parse(path.read_text("utf-8")))]
    assert not found, found
    assert _hand_checked_tolerances(ast.parse("if not 0 < tolerance < 1: pass")) == ["line 1"]
    assert _hand_checked_tolerances(ast.parse("ok = 0 < self.tolerance")) == ["line 1"]
    assert _hand_checked_tolerances(ast.parse("ok = error <= tolerance")) == []


def _last_interval_summaries(tree) -> list[str]:
    """Calls of a run's ``summarise`` (by its name, or a name it was imported as) without ``unsettled_mean=True``:
    an unsettled sequence read by its last interval, where faultslip.run reports the mean of those after the
    first."""
    names = {"summarise"} | {alias.asname for node in ast.walk(tree) if isinstance(node, ast.ImportFrom)
                             for alias in node.names if alias.name == "summarise" and alias.asname}
    found = []
    for node in ast.walk(tree):
        if isinstance(node, ast.Call) and (_call_name(node.func) or "").split(".")[-1] in names:
            mean = next((k.value for k in node.keywords if k.arg == "unsettled_mean"), None)
            if not (isinstance(mean, ast.Constant) and mean.value is True):
                found.append(f"line {node.lineno}")
    return found


def test_an_unsettled_run_is_read_one_way_in_the_package():
    """Every summary of a 2-D or 3-D run in the package reads an unsettled sequence as faultslip.run reports it
    (``summarise(..., unsettled_mean=True)``): a study's cells had read the last interval and event where the run
    of the same scene read the mean. Only benchmarks whose saved rows were read the other way leave it out."""
    found = []
    for module, path in MODULES.items():
        found += [f"{module} {where}" for where in _last_interval_summaries(ast.parse(path.read_text("utf-8")))]
    assert not found, found
    assert _last_interval_summaries(ast.parse("s = summarise(run)")) == ["line 1"]
    assert _last_interval_summaries(ast.parse("s = analysis.summarise(run, 1e-3, unsettled_mean=False)")) == ["line 1"]
    assert _last_interval_summaries(ast.parse("from a import summarise as read\nread(run)")) == ["line 2"]
    assert _last_interval_summaries(ast.parse("s = summarise(run, tolerance, unsettled_mean=True)")) == []


BENCHMARKS = PACKAGE.parent / "benchmarks"


def _unstamped(text: str) -> list[str]:
    """What keeps a benchmark's source from stamping its results in one place (benchmarks/provenance.py): the
    machine's name built by hand, or a results file written as JSON without :func:`provenance.stamp` (or the
    profile benchmark's ``write_results``, which stamps)."""
    problems = []
    if re.search(r"platform\.(machine|processor|python_version)\(", text):
        problems.append("builds the machine's name itself")
    writes_results = re.search(r"[\"']results[\"']", text) and re.search(r"json\.dumps?\(", text)
    if writes_results and "stamp()" not in text and "write_results(" not in text:
        problems.append("writes a results file without provenance.stamp()")
    return problems


def test_every_benchmark_result_is_stamped_in_one_place():
    """A figure in benchmarks/results/ is only comparable with one re-measured elsewhere (another host, newer
    packages) when its file says what it was measured with: machine, packages and date, from
    benchmarks/provenance.py's ``stamp``, which readme.py prints under each table. No benchmark stamps its own."""
    # hierarchy_chart.py reads results and writes data/fault_2d_hierarchy.json, a table the library reads: the
    # results it reads carry their stamps
    found = {path.name: problems for path in sorted(BENCHMARKS.glob("*.py"))
             if path.name not in ("provenance.py", "hierarchy_chart.py")
             for problems in [_unstamped(path.read_text(encoding="utf-8"))] if problems}
    assert found == {}, found
    assert "platform." not in (BENCHMARKS / "hierarchy_chart.py").read_text(encoding="utf-8")


def test_the_stamp_check_sees_what_it_must():
    hand_made = 'out = ROOT / "results" / "x.json"\nout.write_text(json.dumps({"machine": platform.machine()}))'
    assert _unstamped(hand_made) == ["builds the machine's name itself",
                                     "writes a results file without provenance.stamp()"]
    assert _unstamped('out = ROOT / "results" / "x.json"\nout.write_text(json.dumps({**stamp(), "a": 1}))') == []
    assert _unstamped('print(json.dumps({"a": 1}))') == []  # no results file


def test_no_test_puts_the_clone_on_sys_path():
    """A test that inserts the repository (or benchmarks/) into sys.path for the rest of its process makes every
    pool worker spawned later import faultslip from the clone's source, without its compiled extensions, while the
    test process uses the installed package: the two then differ in their last bits (CI found this)."""
    root = Path(__file__).resolve().parents[1]
    offenders = [str(path.relative_to(root)) for path in root.rglob("*.py")
                 if re.search(r"^\s*sys\.path\.(insert|append)\(", path.read_text(encoding="utf-8"), flags=re.M)
                 and path.name != "conftest.py"]
    assert not offenders, offenders


def test_tests_load_a_benchmark_through_one_loader():
    """A benchmark script puts the clone on sys.path when it loads (it runs as a script from a clone):
    conftest.load_benchmark puts sys.path back afterwards, and is the only place a test loads one by its path."""
    root = Path(__file__).resolve().parents[1]
    offenders = [str(path.relative_to(root)) for path in root.rglob("*.py")
                 if "spec_from_file_location" in path.read_text(encoding="utf-8") and path.name != "conftest.py"
                 and path.name != Path(__file__).name]
    assert not offenders, offenders


def test_the_slowest_files_are_handed_out_first():
    """conftest.SLOWEST_FIRST names files that exist (a renamed file would silently drop back to the end of the
    queue), and the collection puts their tests first, in that order, the others after them in their own order."""
    from types import SimpleNamespace

    from conftest import SLOWEST_FIRST, pytest_collection_modifyitems

    root = Path(__file__).resolve().parents[2]
    assert all((root / path).is_file() for path in SLOWEST_FIRST), SLOWEST_FIRST
    items = [SimpleNamespace(nodeid=f"{path}::test_{n}") for n, path in enumerate(
        ["tests/a.py", SLOWEST_FIRST[1], "tests/b.py", SLOWEST_FIRST[0], "tests/a.py"])]
    pytest_collection_modifyitems(None, items)
    assert [item.nodeid for item in items] == [f"{SLOWEST_FIRST[0]}::test_3", f"{SLOWEST_FIRST[1]}::test_1",
                                               "tests/a.py::test_0", "tests/b.py::test_2", "tests/a.py::test_4"]


#: the SI units a docstring writes in parentheses, by the kind takes_units declares
_DOC_UNITS = {"length": {"m"}, "area": {"m^2"}, "speed": {"m/s"}, "time": {"s"}, "rate": {"1/s", "1/yr"},
              "pressure": {"Pa"}, "stress_per_length": {"Pa/m"}, "force": {"N"}, "stiffness": {"N/m"},
              "damping": {"N s/m"}, "slowness": {"s/m"}, "inverse_length": {"1/m"}, "mass": {"kg"},
              "mass_per_area": {"kg/m^2"}, "stress_damping": {"Pa s/m"},
              "moment": {"N m"}, "moment_rate": {"N m/yr"}, "frequency": {"Hz"}, "acceleration": {"m/s^2"}}
_NUMERIC = ("float", "array", "array_like", "int", "list", "sequence")


def _documented_parameters(doc: str) -> dict:
    """numpydoc Parameters: name -> (its type line, its description)."""
    if "Parameters\n----------\n" not in doc:
        return {}
    body = re.split(r"\n\n[A-Z][a-z]+\n-{3,}", doc.split("Parameters\n----------\n", 1)[1])[0]
    found, names = {}, []
    for line in body.splitlines():
        head = re.match(r"^(\w[\w, ]*?)\s*:\s*(.*)$", line)
        if head and not line.startswith(" "):
            names = [name.strip() for name in head.group(1).split(",")]
            found.update({name: (head.group(2), "") for name in names})
        else:
            found.update({name: (found[name][0], found[name][1] + " " + line.strip()) for name in names})
    return found


def _units_in(text: str) -> set:
    return {unit.strip() for group in re.findall(r"\(([^()]*)\)", text) for unit in re.split(r"[,;]| or ", group)}


def test_every_public_quantity_takes_units():
    """Units at every boundary, the Python API's too (MetPy's calc): a public function's or class's parameter that
    is a number with a unit in its docstring ("(m)", "(N m/yr)") is declared to ``faultslip.units.takes_units``
    or says it takes a Quantity (it converts itself); and each declared kind is the unit the docstring states."""
    import inspect

    from faultslip import api

    every_unit = set().union(*_DOC_UNITS.values())
    undeclared, mismatched = [], []
    for name, where in api.public_names().items():
        function = api.resolve(where)
        if not (inspect.isfunction(function) or inspect.isclass(function)):
            continue
        declared = getattr(function, "__units__", {})
        try:
            parameters = inspect.signature(function).parameters
        except ValueError:  # a class without a signature of its own takes nothing to convert
            continue
        doc = (inspect.getdoc(function) or "").replace("Attributes\n----------\n", "Parameters\n----------\n")
        for parameter, (kind_line, text) in _documented_parameters(doc).items():
            units = _units_in(kind_line + " " + text) & every_unit
            if parameter not in parameters or not units:
                continue
            if parameter in declared:
                spec = declared[parameter]
                kinds = [spec[0]] if isinstance(spec, tuple) else spec.split("|")
                if not units & set().union(*(_DOC_UNITS[kind] for kind in kinds)):
                    mismatched.append(f"{name}({parameter}): declared {spec}, documented {sorted(units)}")
            elif kind_line.split(",")[0].split(" ")[0] in _NUMERIC and "Quantity" not in kind_line:
                undeclared.append(f"{name}({parameter})")
    assert not undeclared, f"public quantities that take no units: {undeclared}"
    assert not mismatched, f"declared kinds that are not the documented units: {mismatched}"


def test_the_units_check_sees_what_it_must():
    doc = "Parameters\n----------\nwidth : float\n    W (m).\nflag : bool\n    On (m).\n\nReturns\n-------\nfloat"
    found = _documented_parameters(doc)
    assert _units_in(" ".join(found["width"])) == {"m"} and found["flag"][0] == "bool"
