"""`dnarod`: the toolkit's command line. Subcommands live in workflows/commands/."""
from __future__ import annotations

import argparse
import importlib
import os
import pkgutil
import sys
from pathlib import Path

from dna_models.errors import DnarodError
from dnarod import commands, validate


def _subcommand_modules():
    for info in sorted(pkgutil.iter_modules(commands.__path__), key=lambda m: m.name):
        if info.name.startswith("_"):
            continue
        yield importlib.import_module(f"dnarod.commands.{info.name}")


def version() -> str:
    """The version and git revision of the build, as `rodsim --version` prints them and
    every output file records them (rodcore's, compiled in)."""
    try:
        import rodcore
    except ImportError as e:
        return f"dnarod (rodcore not importable: {e}; scripts/build.sh builds it)"
    return f"dnarod {rodcore.__version__} (git revision {rodcore.git_revision})"


class _Version(argparse.Action):
    """--version, resolved only when asked (rodcore is imported then, not on every run)."""

    def __init__(self, option_strings, dest, **kw):
        super().__init__(option_strings, dest, nargs=0, help="print the version and git revision and exit")

    def __call__(self, parser, namespace, values, option_string=None):
        print(version())
        parser.exit()


def build_parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(
        prog="dnarod",
        description="DNA coarse-graining and comparison toolkit: a geometrically exact "
                    "elastic rod (rodsim) side by side with all-atom GROMACS MD.")
    parser.add_argument("--version", action=_Version)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND")
    for mod in _subcommand_modules():
        p = sub.add_parser(mod.NAME, help=mod.HELP, description=getattr(mod, "DESCRIPTION", mod.HELP),
                           formatter_class=argparse.RawDescriptionHelpFormatter)
        mod.add_arguments(p)
        p.set_defaults(_run=mod.run)
    return parser


def _new_folder(args) -> Path | None:
    """The output folder a command is about to create (None if it exists or there is none)."""
    out = getattr(args, "output", None)
    if not out:
        return None
    p = Path(out)
    return None if p.exists() else p


def _remove_if_empty(folder: Path | None) -> None:
    """A command that failed leaves no empty output folder behind (one it made itself)."""
    if folder is not None and folder.is_dir() and not any(folder.iterdir()):
        folder.rmdir()


def main(argv=None) -> int:
    parser = build_parser()
    try:
        args = parser.parse_args(argv)
    except SystemExit as e:     # argparse's refusal (exit 2, with the option) or --help (0): a status here too
        return int(e.code or 0)
    if not getattr(args, "_run", None):
        parser.print_help()
        return 2
    made = _new_folder(args)
    try:
        return int(args._run(args) or 0)
    except DnarodError as e:
        _remove_if_empty(made)
        validate.remove_made_folders()
        print(f"dnarod {args.command}: error: {e}", file=sys.stderr)
        return 2
    except KeyboardInterrupt:
        _remove_if_empty(made)
        validate.remove_made_folders()
        print(f"dnarod {args.command}: interrupted", file=sys.stderr)
        return 130
    except BrokenPipeError:
        # the reader stopped reading (`dnarod helical-params X | head -3`): that ends the
        # output, not in error; stdout goes to /dev/null so that the interpreter's last
        # flush does not raise again
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0


if __name__ == "__main__":
    sys.exit(main())
