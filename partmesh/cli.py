"""The ``partmesh`` command line (SPEC §6). Every command is a thin wrapper
around a documented Python function, reached through the package (``pm``),
whose names load on first use: building the parser, and so ``partmesh
--help``, imports no solver, xarray, SciPy or matplotlib."""

from __future__ import annotations

import argparse
import sys
from pathlib import Path

import partmesh as pm
from partmesh.cases.errors import InputError, SolverFailed


def _settings(pairs: list[str]) -> dict:
    """``key=value`` strings as a dict (values stay strings; the scene
    converts them to the parameter's type)."""
    out = {}
    for pair in pairs or []:
        key, sep, value = pair.partition("=")
        if not sep or not key:
            raise InputError(f"--set expects key=value, got {pair!r}.")
        out[key.strip()] = value.strip()
    return out


def cmd_cases(args) -> int:
    for name in pm.scenes():
        print(f"{name}: {pm.registry.describe(name)}")
        print(f"    {pm.scene(name).description}")
        for key, value in pm.scene_parameters(name).items():
            print(f"    {key} = {value!r}")
    return 0


def cmd_run(args) -> int:
    pairs = _settings(args.set)
    scene_keys = set(pm.scene_parameters(args.case))
    scene = pm.scene(args.case, **{k: v for k, v in pairs.items() if k in scene_keys})
    settings = {"progress": not args.quiet}
    if args.dx is not None:
        settings["dx"] = args.dx
    if args.t_end is not None:
        settings["t_end"] = args.t_end
    if args.cfl is not None:
        settings["cfl"] = args.cfl
    if args.ensembles != 1:
        settings.update(ensembles=args.ensembles, scheduler=args.scheduler)
    if args.particles:
        settings["particles"] = str(Path(args.output).with_suffix("")) + "_particles.nc"
    checkpoint = Path(str(args.output) + ".checkpoint")
    if args.checkpoint_every is not None or args.resume:
        settings.update(checkpoint=checkpoint, resume=args.resume)
        if args.checkpoint_every is not None:
            settings["checkpoint_every"] = args.checkpoint_every
    settings.update(_settings(args.option))
    settings.update({k: v for k, v in pairs.items() if k not in scene_keys})  # --set of a solver setting (ppc)
    try:
        ds = pm.run(scene, args.method, **settings)
    except SolverFailed as failure:
        if failure.partial is not None:
            pm.write(failure.partial, args.output)
            print(f"partial result written to {args.output}", file=sys.stderr)
        raise
    pm.write(ds, args.output)
    checkpoint.unlink(missing_ok=True)  # the run is complete
    if not args.quiet:
        print(f"{args.case} with {args.method}: {ds.attrs['n_steps']} steps, {ds.attrs['wall_seconds']:.2f} s "
              f"(+{ds.attrs['compile_seconds']:.2f} s compile) -> {args.output}")
    return 0


def cmd_sweep(args) -> int:
    values = {key: [v.strip() for v in value.split(",")] for key, value in _settings(args.set).items()}
    settings = _settings(args.option)
    for key in ("t_end", "cfl"):
        if getattr(args, key) is not None:
            settings[key] = getattr(args, key)
    dx = [float(v) for v in args.dx.split(",")] if args.dx else [None]
    records = pm.sweep(args.case, [m.strip() for m in args.methods.split(",")], dx, values, args.output, settings,
                       scheduler=args.scheduler, workers=args.workers, progress=not args.quiet)
    counts = {status: sum(r["status"] == status for r in records) for status in ("ran", "done before", "failed")}
    print(f"{len(records)} runs of {args.case}: {counts['ran']} ran, {counts['done before']} done before, "
          f"{counts['failed']} failed -> {args.output}")
    for r in records:
        if r["status"] == "failed":
            print(f"failed: {r['name']}: {r['message']}", file=sys.stderr)
    return 3 if counts["failed"] else 0


def _per_method(pairs, what: str, methods=None) -> dict:
    """``METHOD=V1[,V2...]`` strings as method -> list of floats."""
    out = {}
    for pair in pairs or []:
        method, sep, values = pair.partition("=")
        try:
            numbers = [float(v) for v in values.split(",")]
        except ValueError:
            numbers = None
        if not sep or not numbers or (methods is not None and method not in methods):
            raise InputError(f"{what} expects METHOD=DX[,DX...]{' for one of ' + ', '.join(methods) if methods else ''}, "
                             f"got {pair!r}.")
        out[method] = numbers
    return out


def cmd_study(args) -> int:
    settings = _settings(args.option)
    options = dict(scheduler=args.scheduler, workers=args.workers, progress=not args.quiet)
    if args.ladder:
        table = pm.study_ladder(_per_method(args.ladder, "--ladder"), Path(args.output), args.configuration,
                                settings, **options)
        print(table[[c for c in ("run", "method", "dx", "wall_seconds", "wall_force_peak_fitted",
                                 "wall_impulse_final") if c in table]].to_string(index=False))
        print(f"resolution study written to {Path(args.output) / 'sensitivity'}")
        return 0
    if not args.methods:
        raise InputError("partmesh study needs --methods (the study) or --ladder (a resolution study).")
    methods = [m.strip() for m in args.methods.split(",")]
    dx = {m: v[0] for m, v in _per_method(args.dx, "--dx", methods).items()}
    table = pm.study(methods, [p.strip() for p in args.parts.split(",")], Path(args.output), dx, settings, **options)
    columns = [c for c in ("configuration", "method", "wall_peak_pressure_fitted", "wall_arrival_time",
                           "wall_force_peak_fitted", "wall_impulse_final", "wall_seconds") if c in table]
    print(table[columns].to_string(index=False))
    print(f"study written to {args.output}")
    return 0


def cmd_compare(args) -> int:
    table = pm.report(args.runs, reference=args.reference, output=args.output)
    print(table.to_string(index=False))
    print(f"report written to {args.output}")
    return 0


def cmd_demo(args) -> int:
    pm.demo.demo(Path(args.output), progress=not args.quiet)
    return 0


def cmd_warm(args) -> int:
    unknown = [m for m in args.methods if m not in pm.demo.GAS_METHODS]
    if unknown:
        raise InputError(f"warm compiles {', '.join(pm.demo.GAS_METHODS)}; got {', '.join(map(repr, unknown))}.")
    pm.warm(pm.demo.plan(args.methods or pm.demo.GAS_METHODS), processes=args.processes, progress=not args.quiet)
    return 0


def cmd_bench(args) -> int:
    pm.bench.bench(args.output, size=args.size, quick=args.quick)
    return 0


def _runs_on_dask(p, output: str, what: str) -> None:
    """The options of a command whose runs go to Dask: seed, scheduler, workers, output folder, quiet."""
    p.add_argument("--seed", type=int, help="random seed of the stochastic methods")
    p.add_argument("--scheduler", help="Dask scheduler address (default: a LocalCluster)")
    p.add_argument("--workers", type=int, help="LocalCluster worker processes (default: one per core)")
    p.add_argument("-o", "--output", default=output, help=what)
    p.add_argument("--quiet", action="store_true")


def parser() -> argparse.ArgumentParser:
    p = argparse.ArgumentParser(prog="partmesh", description="Particle and mesh methods on the same scenes, compared.")
    sub = p.add_subparsers(dest="command", required=True)

    sub.add_parser("cases", help="list scenes and their parameters").set_defaults(func=cmd_cases)

    r = sub.add_parser("run", help="run one scene with one method")
    r.add_argument("case")
    r.add_argument("--method", "-m", required=True)
    r.add_argument("--dx", type=float, help="cell size (fv, dsmc) or initial particle spacing (sph) [m]")
    r.add_argument("--set", action="append", metavar="KEY=VALUE",
                   help="scene parameter, or a setting of the method such as ppc (repeatable)")
    r.add_argument("--option", action="append", metavar="KEY=VALUE",
                   help="solver setting, e.g. limiter=minmod, riemann=hll (repeatable)")
    r.add_argument("--t-end", type=float, dest="t_end")
    r.add_argument("--cfl", type=float)
    r.add_argument("--seed", type=int, help="random seed (particle methods)")
    r.add_argument("--ensembles", type=int, default=1,
                   help="average this many runs with seeds SEED, SEED+1, ... (stochastic methods), on Dask")
    r.add_argument("--scheduler", help="Dask scheduler address for --ensembles (default: a LocalCluster)")
    r.add_argument("-o", "--output", required=True)
    r.add_argument("--particles", action="store_true",
                   help="also write the last particle state beside the output, as <output>_particles.nc (sph, wcsph)")
    r.add_argument("--checkpoint-every", type=float, dest="checkpoint_every", metavar="SECONDS",
                   help="save the run's state to <output>.checkpoint every SECONDS of wall time and on "
                        "SIGINT/SIGTERM")
    r.add_argument("--resume", action="store_true", help="continue from <output>.checkpoint")
    r.add_argument("--quiet", action="store_true")
    r.set_defaults(func=cmd_run)

    w = sub.add_parser("sweep", help="every combination of methods, resolutions and --set values, on Dask")
    w.add_argument("case")
    w.add_argument("--methods", "-m", required=True, help="comma-separated, e.g. fv,sph,dsmc")
    w.add_argument("--dx", help="comma-separated cell sizes or particle spacings [m] (default: the scene's)")
    w.add_argument("--set", action="append", metavar="KEY=V1,V2,...",
                   help="swept scene parameter or method setting (repeatable); a setting sweeps only the methods "
                        "that take it")
    w.add_argument("--option", action="append", metavar="KEY=VALUE", help="fixed solver setting (repeatable)")
    w.add_argument("--t-end", type=float, dest="t_end")
    w.add_argument("--cfl", type=float)
    _runs_on_dask(w, "runs", "folder of the runs' files")
    w.set_defaults(func=cmd_sweep)

    s = sub.add_parser("study", help="the blast-array study: wall loads of rod arrays per method, ranked")
    s.add_argument("--methods", "-m", help="comma-separated, e.g. fv,sph,dsmc")
    s.add_argument("--parts", default="moderate",
                   help="comma-separated parts of the study: moderate (11 configurations), and the seed study's "
                        "staggered variants of the square and right-facing triangle: layers (3, 5, 7), standoff "
                        "(0.17, 0.34, 0.51 m; 7 layers at 0.17 m), trap (gaps 0.02-0.16 m), strong (the strong "
                        "blast); variants_inline (the inline variants recorded first) (default: moderate); each "
                        "part's report goes to OUTPUT/<part>/")
    s.add_argument("--dx", action="append", metavar="METHOD=DX",
                   help="spacing of one method's runs [m] (repeatable; default: the scenes')")
    s.add_argument("--option", action="append", metavar="KEY=VALUE",
                   help="solver setting for the methods that take it (repeatable)")
    s.add_argument("--ladder", action="append", metavar="METHOD=DX1,DX2,DX3",
                   help="instead of the study, a resolution study of one configuration: a method's spacings "
                        "(repeatable), with the GCI and speed against error")
    s.add_argument("--configuration", default="circle inline", help="the configuration of --ladder")
    _runs_on_dask(s, "study", "folder of the runs and the report")
    s.set_defaults(func=cmd_study)

    c = sub.add_parser("compare", help="error table of runs of one scene")
    c.add_argument("runs", nargs="+")
    c.add_argument("--reference", default="exact", help="'exact' or a reference result file")
    c.add_argument("-o", "--output", default="report")
    c.set_defaults(func=cmd_compare)

    d = sub.add_parser("demo", help="small end-to-end comparison on built-in defaults")
    d.add_argument("-o", "--output", default="partmesh-demo")
    d.add_argument("--quiet", action="store_true")
    d.set_defaults(func=cmd_demo)

    w = sub.add_parser("warm", help="compile the methods' kernels for the demo's runs, side by side (first run only)")
    w.add_argument("methods", nargs="*", metavar="METHOD", help="fv, sph, dsmc (default: all three)")
    w.add_argument("--processes", type=int, default=None, help="at most this many at once (default: the cores)")
    w.add_argument("--quiet", action="store_true")
    w.set_defaults(func=cmd_warm)

    b = sub.add_parser("bench", help="throughput of each method (JSON)")
    b.add_argument("-o", "--output", default="bench.json")
    b.add_argument("--size", type=int, default=512, help="2D Sedov cells per side")
    b.add_argument("--quick", action="store_true", help="a short run for a smoke check")
    b.set_defaults(func=cmd_bench)
    return p


def main(argv=None) -> int:
    args = parser().parse_args(argv)
    if getattr(args, "seed", None) is not None:
        args.option = (args.option or []) + [f"seed={args.seed}"]
    try:
        return args.func(args)
    except (InputError, FileNotFoundError) as err:
        print(f"partmesh: {err}", file=sys.stderr)
        return 2
    except SolverFailed as err:
        print(f"partmesh: {err}", file=sys.stderr)
        return 3
    except ValueError as err:  # (a file that is not a result, results that cannot be compared)
        if not isinstance(err, (pm.SchemaError, pm.reporting.IncompatibleResults)):
            raise
        print(f"partmesh: {err}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    sys.exit(main())
