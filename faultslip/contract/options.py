"""The options of ``faultslip run`` and ``faultslip simulate``, declared once.

A family names the options its run and simulate take (:class:`~faultslip.contract.registry.Family`'s
``run_options`` and ``simulate_options``); this table says what each one is. The command line builds
its ``run`` and ``simulate`` flags from it, :func:`faultslip.run` and :func:`faultslip.models.simulate`
take the same names as keywords, and a family that does not take an option refuses it in one sentence
naming the family. The module imports nothing, so ``faultslip --help`` stays free of numpy and the
physics (``tests/project/test_architecture.py``).
"""

from __future__ import annotations

from dataclasses import dataclass


@dataclass(frozen=True)
class Option:
    """One option of run or simulate.

    ``name`` is the keyword of :func:`faultslip.run` or :func:`faultslip.models.simulate` and, with
    dashes, the command line's flag; ``kind`` is ``"switch"`` (a flag without a value), ``"count"`` (an
    integer), ``"number"`` (a float, read by the command line's number parser) or ``"text"``;
    ``commands`` the commands that take it; ``family`` whether a family receives it (False: the command
    line itself handles it, writing a file the family's result offers); ``short`` a one-letter flag.
    """

    name: str
    help: str
    kind: str = "text"
    commands: tuple = ("simulate",)
    family: bool = True
    short: str | None = None

    @property
    def flag(self) -> str:
        """The command line's flag: ``--slip-solver`` for ``slip_solver``."""
        return "--" + self.name.replace("_", "-")


#: Every option of run and simulate, in the order ``--help`` lists them.
OPTIONS = {option.name: option for option in (
    Option("output", "write the time series and event table to OUT.nc", short="-o"),
    Option("plot", "draw the run's figure to FILE.png", family=False),
    Option("allow_large", "run even beyond the time, memory and disk budget", "switch", ("run", "simulate")),
    Option("allow_underresolved", "run a discretised fault coarser than 2 elements per L_b, where sequences change "
                                  "character; the answer is then qualitative", "switch", ("run", "simulate")),
    Option("richardson", "run a discretised fault again on elements half the size and declare the discretisation "
                         "error the two show (Richardson extrapolation)", "switch", ("run",)),
    Option("check_starts", "run a discretised fault again from 0.1 and 10 times its start's slip rate and say "
                           "whether it settles to the same cycle (a multistable fault does not)", "switch", ("run",)),
    Option("overwrite", "replace outputs that already exist", "switch"),
    Option("cycles", "number of cycles (default: the scene's, else the family's)", "count"),
    Option("slip_solver", "the slip phase's solver: analytic, RK45, RK23, DOP853, Radau, BDF or LSODA (default auto)"),
    Option("rtol", "the integrator's relative tolerance (default: the family's)", "number"),
    Option("stream", "write displacement, slip, slip rate and friction as an obspy Stream: OUT.mseed, or OUT.sac "
                     "(one file per channel)"),
    Option("events", "write the events as QuakeML (OUT.xml) with Mw from M0 (fault scenes)"),
    Option("sampling_rate", "stream sampling rate in Hz (default: 20 samples per slip phase, within 2e6 samples)",
           "number", family=False),
    Option("start_time", "UTC time of model time 0, ISO 8601 (default 2000-01-01)", family=False),
    Option("output_dir", "a discretised fault's run folder: SEAS station files, slip profiles, events and netCDF, "
                         "with checkpoints for --resume"),
    Option("resume", "continue a discretised fault's run from its last checkpoint", "switch"),
    Option("estimate", "print what it would need (CPU time, memory, disk) from the family's cost model, and stop",
           "switch", ("run", "simulate"), family=False),
)}

#: What every family receives whatever it declares (where the run's output goes, for a disk estimate; the
#: budget's override; whether outputs may be replaced); a family with no use for them ignores them.
UNIVERSAL = ("output", "allow_large", "overwrite")


def options_of(command: str) -> list[Option]:
    """The options of ``command`` (``"run"`` or ``"simulate"``), in the order ``--help`` lists them.

    Parameters
    ----------
    command : str
        ``"run"`` or ``"simulate"``.

    Returns
    -------
    list of Option
        Its options.
    """
    return [option for option in OPTIONS.values() if command in option.commands]


#: Options every command spells and means the same way (``tests/project/test_front_door.py`` checks each command's parser
#: against it): the flag, and its one help text. ``-o`` is always a file a command writes, ``--output-dir`` always a
#: folder.
COMMON = {
    "--json": "print one JSON object",
    "--overwrite": "replace outputs that already exist",
    "--allow-large": "run even beyond the time, memory and disk budget",
}
#: What the help of ``-o``/``--output`` and of ``--output-dir`` may and may not say.
FILE_OPTION, FOLDER_OPTION = "-o", "--output-dir"
#: Old spellings kept for one release: (command, old flag) -> the flag to use now.
DEPRECATED = {(command, flag): "--output-dir" for command in ("critical", "bench", "stability", "rate-state bench")
              for flag in ("-o", "--output")}
DEPRECATED[("decay", "--cycles")] = "--cycles-between"
