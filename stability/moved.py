"""Old module paths of the package, kept for one release: each is its new module, with a warning.

The package moved to layers for its machinery (``util``, ``core``, ...) and one package per
problem family. Code written against an old path still runs: ``import stability.body`` (or
``from stability.body import RigidBody``, or ``stability.body`` after ``import stability``)
gives :mod:`stability.core.body` itself and warns once with a :class:`FutureWarning` that names
the new path. :data:`MOVED` is the table; :func:`install` puts its finder on ``sys.meta_path``
(``stability/__init__`` does).

A module whose path became a family's package (``stability.struck`` is now the struck bat's
package, its functions in ``stability.struck.model``) keeps serving its old names instead:
:data:`OLD_NAMES` is that table, and :func:`old_names` the package's ``__getattr__``. So does a
module split in several (``stability.estimators``): its old path imports as a module that holds
no code, only that ``__getattr__``.
"""

from __future__ import annotations

import importlib
import importlib.abc
import importlib.util
import sys
import types
import warnings

#: Old dotted module path -> the module it now is. (``stability.integrate``, which became
#: ``stability.free_body.integrate``, is not here: that path is the function
#: ``stability.integrate``, which a module imported there would replace.)
MOVED = {
    "stability.conventions": "stability.util.conventions",
    "stability.checks": "stability.util.checks",
    "stability.threads": "stability.util.threads",
    "stability.progress": "stability.util.progress",
    "stability.formatting": "stability.util.formatting",
    "stability.compensated": "stability.core.compensated",
    "stability.trig": "stability.core.trig",
    "stability.roots": "stability.core.roots",
    "stability.elliptic": "stability.core.elliptic",
    "stability.quaternions": "stability.core.quaternions",
    "stability.body": "stability.core.body",
    "stability.lock": "stability.output.lock",
    "stability.publish": "stability.output.publish",
    "stability.io": "stability.output.io",
    "stability.store": "stability.output.store",
    "stability.stream": "stability.output.stream",
    "stability.dataset": "stability.output.dataset",
    "stability.figures.style": "stability.plotting.style",
    "stability.scenes.heavy_top": "stability.heavy_top.scene",
    "stability.integrators.heavy_top": "stability.heavy_top.methods",
    "stability.top": "stability.heavy_top.model",
    "stability.exact_top": "stability.heavy_top.exact",
    "stability.gyroscope": "stability.heavy_top.measure",
    "stability.sleeping_top": "stability.heavy_top.measure",
    "stability.study.tops": "stability.heavy_top.studies.common",
    "stability.study.gyroscope": "stability.heavy_top.studies.gyroscope",
    "stability.study.sleeping_top": "stability.heavy_top.studies.sleeping_top",
    "stability.figures.top": "stability.heavy_top.figures",
    "stability.wobble": "stability.earth.wobble",
    "stability.equinoxes": "stability.earth.equinoxes",
    "stability.scenes.lunisolar_earth": "stability.earth.scene",
    "stability.scenes.precessing_axis": "stability.earth.scene",
    "stability.integrators.lunisolar": "stability.earth.methods",
    "stability.study.earth_wobble": "stability.earth.studies.earth_wobble",
    "stability.study.equinoxes": "stability.earth.studies.equinoxes",
    "stability.figures.earth": "stability.earth.figures",
    "stability.figures.equinoxes": "stability.earth.figures",
    "stability.scenes.struck_body": "stability.struck.scene",
    "stability.integrators.struck": "stability.struck.methods",
    "stability.study.bat": "stability.struck.studies.bat",
    "stability.scenes.rolling_body": "stability.rolling.scene",
    "stability.integrators.rolling": "stability.rolling.methods",
    "stability.study.rolling": "stability.rolling.studies.rolling",
    "stability.artefacts": "stability.engine_body.measure",
    "stability.scenes.engine_body": "stability.engine_body.scene",
    "stability.integrators.engine_rules": "stability.engine_body.methods",
    "stability.study.engine_artefacts": "stability.engine_body.studies.engine_artefacts",
    "stability.figures.artefacts": "stability.engine_body.figures",
    "stability.accessor": "stability.free_body.accessor",
    "stability.schema": "stability.ensemble.schema",
    "stability.scene_ensemble": "stability.ensemble.chunks",
    "stability.scene_run": "stability.ensemble.run",
    "stability.memory": "stability.ensemble.memory",
    "stability.periodic": "stability.analysis.periodic",
    "stability.drift": "stability.free_body.work_precision.drift",
    "stability.gpu": "stability.engine.gpu",
    "stability.gpu.bench": "stability.engine.gpu.bench",
    "stability.gpu.device": "stability.engine.gpu.device",
    "stability.gpu.kernels": "stability.engine.gpu.kernels",
    "stability.gpu.methods": "stability.engine.gpu.methods",
    "stability.gpu.propagate": "stability.free_body.propagate_gpu",
    "stability.gpu.retarget": "stability.engine.gpu.retarget",
    "stability.gpu.run": "stability.engine.gpu.run",
    "stability.scenes.spec": "stability.engine.scene",
    "stability.scenes.user": "stability.engine.user_scene",
    "stability.scenes.registry": "stability.registry",
    "stability.bench": "stability.cli.bench",
    "stability.scenes.free_body": "stability.free_body.scene",
    "stability.scenes.free_body_attitude": "stability.free_body.scene_attitude",
    "stability.analytic": "stability.free_body.model",
    "stability.exact": "stability.free_body.exact",
    "stability.exact_attitude": "stability.free_body.exact_attitude",
    "stability.attitude": "stability.free_body.attitude",
    "stability.driver": "stability.free_body.propagate",
    "stability.timescales": "stability.free_body.timescales",
    "stability.reference": "stability.free_body.reference",
    "stability.polhodes": "stability.free_body.polhodes",
    "stability.figures.poinsot": "stability.free_body.figures",
    "stability.flipsweep": "stability.free_body.tennis_racket.flipsweep",
    "stability.study.tennis_racket": "stability.free_body.tennis_racket.study",
    "stability.figures.tennis": "stability.free_body.tennis_racket.figures",
    "stability.stabilitymap": "stability.free_body.stability_map.measure",
    "stability.study.stability_map": "stability.free_body.stability_map.study",
    "stability.figures.stability_map": "stability.free_body.stability_map.figures",
    "stability.shapes": "stability.free_body.stability_map.shapes",
    "stability.workprecision": "stability.free_body.work_precision.measure",
    "stability.sweeps": "stability.free_body.work_precision.sweeps",
    "stability.study.work_precision": "stability.free_body.work_precision.study",
    "stability.figures.work_precision": "stability.free_body.work_precision.figures",
    "stability.twisting": "stability.free_body.twisting_racket.measure",
    "stability.geometric_phase": "stability.free_body.twisting_racket.geometric_phase",
    "stability.study.twisting_racket": "stability.free_body.twisting_racket.study",
    "stability.figures.twisting": "stability.free_body.twisting_racket.figures",
}

#: Old module path that is now a package (or a module that kept only its old names) -> each
#: public name the old module held -> the module that holds it now.
OLD_NAMES = {
    "stability.earth": dict.fromkeys((
        "earth_moments", "earth", "euler_period", "oblate_euler_period", "MASS",
        "EQUATORIAL_RADIUS", "POLAR_MOMENT_FACTOR", "DYNAMICAL_ELLIPTICITY",
        "EQUATORIAL_ASYMMETRY", "SIDEREAL_DAY", "CHANDLER_PERIOD_DAYS", "DAY", "ARCSEC"),
        "stability.earth.model"),
    "stability.struck": dict.fromkeys((
        "INCH", "BAT_PROFILE", "HOLD", "PIVOT", "STRIKE", "StruckBody", "baseball_bat",
        "tennis_racket", "BODIES", "check_pivot", "centre_of_percussion", "reaction_impulse",
        "hand_velocity", "measure_strikes"), "stability.struck.model"),
    "stability.rolling": dict.fromkeys((
        "SHAPES", "G", "rolls", "rolling_acceleration", "slipping_acceleration",
        "slipping_spin_rate", "launch_formulas", "start_states", "measure_incline",
        "measure_launches"), "stability.rolling.model"),
    "stability.ensemble": {
        **dict.fromkeys(("run_ensemble", "run_ensembles", "EnsembleSummary", "completed"),
                        "stability.free_body.ensemble"),
        **dict.fromkeys(("max_angular_speed", "seed_sequence", "perturbed_starts", "RNG_CHUNK"),
                        "stability.free_body.starts"),
        **dict.fromkeys(("ensemble_memory", "STREAM_CHUNK_MEMBERS", "DEFAULT_DIVERGENCE_TOLERANCE",
                         "LARGE_RUN_BYTES", "DEFAULT_LEVELS", "PEAK_COPIES", "MAX_STEPS"),
                        "stability.free_body.plan"),
        **dict.fromkeys(("run_streamed", "EnsembleChunks"), "stability.free_body.streamed"),
    },
    "stability.ensemble.schema": {
        name: f"stability.{family}.schema" for family, names in (
            ("free_body", ("TRAJECTORY", "TENNIS_RACKET", "STABILITY_MAP", "WORK_PRECISION",
                           "TWISTING_RACKET")),
            ("engine_body", ("ENGINE_ARTEFACTS",)), ("earth", ("EARTH_WOBBLE", "EQUINOXES")),
            ("heavy_top", ("GYROSCOPE", "SLEEPING_TOP")), ("struck", ("BAT",)),
            ("rolling", ("ROLLING",)), ("dissipation", ("EXPLORER", "DUAL_SPIN")))
        for name in names},
    "stability.study.config": {
        **dict.fromkeys(("FIGURE_FORMATS", "preset_names", "method_names",
                         "tossed_body_sections", "MEMBER_BYTES", "check_memory", "output_section",
                         "run_section", "run_keys", "scheduler_key", "check_run", "stored_run"),
                        "stability.study.sections"),
        **dict.fromkeys(("output_files", "write_outputs"), "stability.study.outputs"),
        **dict.fromkeys(("STUDY_KEY", "StudyKind", "StudySummary", "run_rows", "SummaryTable"),
                        "stability.study.kind"),
    },
    "stability.engine.gpu": dict.fromkeys(("propagate_gpu", "propagate_many_gpu"),
                                          "stability.free_body.propagate_gpu"),
    "stability.animation": {
        **dict.fromkeys(("FlipFrames", "flip_frames", "animate_flip"),
                        "stability.free_body.animation"),
        **dict.fromkeys(("TopFrames", "top_frames", "animate_top"),
                        "stability.heavy_top.animation"),
        **dict.fromkeys(("DEFAULT_FPS", "DEFAULT_SIZE", "MAX_FRAMES", "SUFFIXES", "output_path",
                         "write_animation"), "stability.plotting.animation"),
    },
    "stability.figures.animation": {"FlipScene": "stability.free_body.animation",
                                    "TopScene": "stability.heavy_top.animation",
                                    "DPI": "stability.plotting.animation",
                                    "frame_figure": "stability.plotting.animation"},
    "stability.scenes": {"SCENES": "stability.registry", "scene": "stability.registry",
                         "Scene": "stability.engine.scene",
                         "define_scene": "stability.engine.user_scene"},
    "stability.estimators": {
        **dict.fromkeys(("DEPARTURE_FACTOR", "MIN_CROSSINGS", "MIN_POINTS", "WINDOW_ATTRS",
                         "WINDOW_HIGH_FRACTION", "WINDOW_LOW_FACTOR", "member_regimes"),
                        "stability.analysis.regimes"),
        **dict.fromkeys(("ESTIMATE_ATTRS", "flip_estimate", "measured_frequency",
                         "measured_growth_rate",
                         "omega_squared_estimate", "omega_squared_estimates"),
                        "stability.analysis.estimates"),
        **dict.fromkeys(("Members", "members", "perpendicular_amplitude", "sign_change_times",
                         "summary_members",
                         "tracked_members", "zero_crossings"),
                        "stability.analysis.members"),
        **dict.fromkeys(("REGIME_ALGEBRAIC", "REGIME_EXPONENTIAL", "REGIME_MEANINGS",
                         "REGIME_NEUTRAL",
                         "REGIME_OSCILLATION", "REGIME_UNDETERMINED", "perpendicular_axes"),
                        "stability.util.conventions"),
        **dict.fromkeys(("analyse_ensemble", "analysis_headline"),
                        "stability.free_body.tennis_racket.analysis"),
        **dict.fromkeys(("complementary_moduli", "exact_flip_intervals", "flip_statistics",
                         "measured_omega_squared"),
                        "stability.free_body.measure"),
        **dict.fromkeys(("growth_line", "richardson_bias"),
                        "stability.analysis.fits"),
    },
    "stability.figures.impacts": {"bat_figure": "stability.struck.figures",
                                  "rolling_map_figure": "stability.rolling.figures",
                                  "rolling_launch_figure": "stability.rolling.figures"},
}


#: The keys of :data:`OLD_NAMES` whose module is gone: each imports as a module of old names.
SPLIT = ("stability.estimators", "stability.scenes", "stability.animation",
         "stability.figures.animation")


def moved_to(old: str) -> str:
    """Warn that the module ``old`` moved, and return its new path."""
    new = MOVED[old]
    warnings.warn(f"{old} moved to {new}; the old path goes in the next release",
                  FutureWarning, stacklevel=3)
    return new


class OldPathFinder(importlib.abc.MetaPathFinder, importlib.abc.Loader):
    """Finds each old path of :data:`MOVED` and loads it as the module it now is."""

    def find_spec(self, fullname, path=None, target=None):
        if fullname not in MOVED and fullname not in SPLIT:
            return None
        # A split module is a package too, so that its old submodules' paths still import.
        return importlib.util.spec_from_loader(fullname, self, is_package=fullname in SPLIT)

    def create_module(self, spec):
        if spec.name not in MOVED:  # a module split in several: its names, each where it went
            module = types.ModuleType(spec.name, f"Old path of the names in {spec.name}.")
            module.__getattr__ = old_names(spec.name)
            module.__path__ = []
            self.spec = spec
            return module
        module = importlib.import_module(moved_to(spec.name))
        self.spec = module.__spec__  # the import system sets __spec__ to the old path's
        return module

    def exec_module(self, module):
        """Nothing to run (the new module ran when it was imported): its own spec back."""
        module.__spec__ = self.spec

    def get_code(self, fullname):
        """``python -m <old path>``: code that runs the new module as ``__main__``."""
        source = f"import runpy\nrunpy.run_module({moved_to(fullname)!r}, run_name='__main__')\n"
        return compile(source, f"<{fullname}>", "exec")


def old_attribute(name: str):
    """``stability.<name>`` for an old module path (the package's ``__getattr__``);
    AttributeError for any other name."""
    old = f"stability.{name}"
    if old not in MOVED and old not in SPLIT:
        raise AttributeError(f"module 'stability' has no attribute {name!r}")
    return importlib.import_module(old)


def old_names(old: str):
    """The ``__getattr__`` of the module at the old path ``old`` (a key of :data:`OLD_NAMES`):
    each old name from the module that now holds it, imported on first use, with a warning,
    then kept in ``old`` (``from old import name`` asks twice: it warns once); AttributeError for
    any other name (so that ``from old import submodule`` still imports)."""
    where = OLD_NAMES[old]

    def __getattr__(name):
        if name not in where:
            raise AttributeError(f"module {old!r} has no attribute {name!r}")
        warnings.warn(f"{old}.{name} moved to {where[name]}.{name}; the old path goes in the "
                      "next release", FutureWarning, stacklevel=2)
        value = getattr(importlib.import_module(where[name]), name)
        setattr(sys.modules[old], name, value)
        return value

    return __getattr__


def install() -> None:
    """Put the finder of old paths first on ``sys.meta_path`` (once): an old path inside a moved
    package (``stability.gpu.bench``) is then its new module, not a file the path finder would
    find in the new package's folder under the old name."""
    if not any(isinstance(f, OldPathFinder) for f in sys.meta_path):
        sys.meta_path.insert(0, OldPathFinder())
