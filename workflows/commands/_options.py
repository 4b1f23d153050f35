"""Options several subcommands share, spelled one way."""
from __future__ import annotations


def add_output(p, *, help: str, metavar: str = "OUT", required: bool = True, default=None) -> None:
    """-o/--output, the one spelling of a command's output (file or folder). --out, the
    spelling some commands had before, is still accepted and not listed: it is the same
    action under one more name (argparse's table of option strings), so a required
    output given as --out counts as given."""
    kw = {"required": True} if required else {"default": default}
    action = p.add_argument("-o", "--output", metavar=metavar, help=help, **kw)
    p._option_string_actions["--out"] = action
