"""Scenes: a scene file read, built and run (see examples/scenes/README.md for the format)."""

import ctypes
import os
import weakref
from typing import TYPE_CHECKING

from . import _callbacks
from ._errors import check_path
from ._lib import ParticlesPtr, ProgressFn, ScenePtr, StepperPtr, WallsPtr, lib
from .context import _Handle
from .particles import Particles
from .stepper import PathLike, Progress, Stepper, _progress_function
from .walls import Walls

if TYPE_CHECKING:  # pragma: no cover
    from .context import Context  # noqa: F401


class Scene(_Handle):
    """A scene (sinter_scene): materials, particles, walls, submodels and a stepper.

        with sinter.Scene(ctx, "hot_floor.scene") as scene:
            scene.run("out", progress=lambda t, t_end: print(t / t_end))
            print(scene.particles.get("temperature"))

    The scene owns everything it builds. scene.particles, .walls and
    .stepper are borrowed views of its objects: closing the scene closes them,
    and each keeps the scene alive while in use.
    """

    _destroy_function = "sinter_scene_destroy"

    def __init__(self, context: "Context", path: PathLike) -> None:
        """Read, validate and build the scene file at `path` (FileNotFoundError when it does
        not exist; SinterError ERR_PARSE naming the file and line for a bad one)."""
        handle = ScenePtr()
        context._sync_log_level()
        check_path(lib.sinter_scene_load(ctypes.byref(handle), context._ptr, os.fsencode(path)),
                   context._handle, "sinter_scene_load", path)
        super().__init__(context, handle)
        self.path = os.fspath(path)
        self._views = weakref.WeakValueDictionary()
        self._stepper_state = None

    @classmethod
    def load(cls, context: "Context", path: PathLike) -> "Scene":
        """Read, validate and build the scene file at `path`."""
        return cls(context, path)

    def _close_dependents(self):
        for view in list(self._views.values()):
            view.close()

    def _forget(self):
        self._stepper_state = None  # models and the observer given to the scene's stepper

    def _view(self, name, make):
        view = self._views.get(name)
        if view is None or view.closed:
            view = make()
            self._views[name] = view
        return view

    @property
    def particles(self) -> Particles:
        """The scene's Particles (borrowed)."""
        def make():
            handle = ParticlesPtr()
            self._check(lib.sinter_scene_get_particles(self._ptr, ctypes.byref(handle)),
                        "sinter_scene_get_particles")
            return Particles._borrowed_from(self, handle)

        return self._view("particles", make)

    @property
    def walls(self) -> Walls:
        """The scene's Walls (borrowed)."""
        def make():
            handle = WallsPtr()
            self._check(lib.sinter_scene_get_walls(self._ptr, ctypes.byref(handle)),
                        "sinter_scene_get_walls")
            return Walls._borrowed_from(self, handle)

        return self._view("walls", make)

    @property
    def stepper(self) -> Stepper:
        """The scene's Stepper (borrowed); its .particles and .walls are the scene's."""
        def make():
            handle = StepperPtr()
            self._check(lib.sinter_scene_get_stepper(self._ptr, ctypes.byref(handle)),
                        "sinter_scene_get_stepper")
            return Stepper._borrowed_from(self, handle, self.particles, self.walls)

        return self._view("stepper", make)

    @property
    def end_time(self) -> float:
        """The scene's end time [s]."""
        end_time = ctypes.c_double()
        self._check(lib.sinter_scene_end_time(self._ptr, ctypes.byref(end_time)),
                    "sinter_scene_end_time")
        return end_time.value

    @end_time.setter
    def end_time(self, end_time: float) -> None:
        """Change the end time [s] (after a pour, counted from its end), also after a restart."""
        self._check(lib.sinter_scene_set_end_time(self._ptr, float(end_time)),
                    "sinter_scene_set_end_time")

    def restart(self, checkpoint: PathLike) -> None:
        """Restore the scene to a checkpoint its run wrote; the next run() continues it.

        A checkpoint of another scene is refused (InvalidArgument naming the difference), a
        missing file raises FileNotFoundError, and nothing changes. A scene file edited since
        the run: its explicit-stepper dt and [output] interval and checkpoint_interval win,
        each logged as a warning (the run then differs from an uninterrupted one).
        """
        check_path(lib.sinter_scene_restart(self._ptr, os.fsencode(checkpoint)),
                   self._context._handle, "sinter_scene_restart", checkpoint)

    def write_checkpoint(self, path: PathLike) -> None:
        """Write the scene's checkpoint (the stepper's state and where the run stands)."""
        self._check(lib.sinter_scene_checkpoint_write(self._ptr, os.fsencode(path)),
                    "sinter_scene_checkpoint_write")

    def check(self) -> None:
        """Make the checks a run makes before its first step, without stepping
        (sinter_scene_check): the output plan, the particles' values, no particle behind a wall
        or outside the domain, no two with the same centre. Raises InvalidArgument (or
        BusyError while a field view is out) naming what is wrong."""
        self._check(lib.sinter_scene_check(self._ptr), "sinter_scene_check")

    def compact(self) -> None:
        """Run the scene's [compact] section on its particles now (sinter_scene_compact): the
        triaxial compaction that run() makes before the first step of a scene without [pour],
        for a host that steps the scene itself. Raises SinterError (SINTER_ERR_STATE) without a
        [compact] section."""
        self._check(lib.sinter_scene_compact(self._ptr), "sinter_scene_compact")

    def run(self, out_dir: PathLike, progress: Progress = None) -> bool:
        """Run to the end time, writing the [output] files into out_dir (created if missing).

        progress(time, end_time) [s] is called after each output sample; a true
        result stops the run (the library then writes checkpoint.bin and the plot).
        progress=True shows a progress bar (tqdm when installed, else a line on stderr).
        Returns True when the run reached its end, False when progress stopped it.
        An exception in progress (or in any Python callback of the scene's objects)
        is raised here. Ctrl-C ends the run after its current step, the library writes
        checkpoint.bin and the plot, and KeyboardInterrupt is raised (restart() and run()
        continue it).
        """
        asked_to_stop = []
        if progress is True:
            bar = _progress_function(True, 0.0, self.end_time)

            def progress(time: float, end_time: float) -> None:
                bar(time, end_time, final=time >= end_time)
        if progress is None or progress is False:
            function = ProgressFn()
        else:
            def trampoline(time, end_time, user):
                try:
                    if progress(time, end_time):
                        asked_to_stop.append(time)
                        return 1
                    return 0
                except BaseException as exception:
                    _callbacks.store(exception)
                    return 1

            function = ProgressFn(trampoline)
        self._context._sync_log_level()
        status = _callbacks.call(self._context._handle, "sinter_scene_run", lib.sinter_scene_run,
                                 self._ptr, os.fsencode(out_dir), function, None,
                                 stopped=lambda: bool(asked_to_stop), interruptible=True)
        return status == 0

    def __repr__(self) -> str:
        return "<sinter.Scene %s>" % ("closed" if self.closed else repr(self.path))
