"""mdrun's log (md.log): the energy blocks it writes every nstlog steps.

GROMACS prints each block as

               Step           Time
                  0        0.00000

       Energies (kJ/mol)
               Bond            U-B    Proper Dih.  ...
        6.23572e+03    6.45653e+03    5.83083e+03  ...

the names and their values in rows of right-aligned 15-character columns, a blank
line after the last row. A value GROMACS cannot print as a number is "nan" or "inf".
"""
from __future__ import annotations

import re
from pathlib import Path

_COLUMN = 15
_STEP_TIME = re.compile(r"\s+Step\s+Time\s*$")


def last_energy_block(log_text: str) -> list[str]:
    """The lines of the last "Step Time" block of LOG_TEXT (step line to the end of its
    energies), blank lines dropped; [] when there is none."""
    lines = log_text.splitlines()
    starts = [i for i, ln in enumerate(lines) if _STEP_TIME.match(ln)]
    if not starts:
        return []
    i = j = starts[-1]
    # the step header, its values, a blank line, then the energies up to the next blank line
    while j < len(lines) and (j < i + 3 or lines[j].strip()):
        j += 1
    return [ln for ln in lines[i:j] if ln.strip()]


def block_energies(block: list[str]) -> tuple[int, dict[str, float]]:
    """(step, {name: value}) of a block from last_energy_block. A block cut short (mdrun
    still writing it) gives the rows complete so far."""
    step = int(block[1].split()[0]) if len(block) > 1 else -1
    values: dict[str, float] = {}
    rows = block[3:] if len(block) > 2 and "Energies" in block[2] else []
    for names, vals in zip(rows[0::2], rows[1::2]):
        keys = [names[k:k + _COLUMN].strip() for k in range(0, len(names), _COLUMN)]
        nums = [vals[k:k + _COLUMN].strip() for k in range(0, len(vals), _COLUMN)]
        for key, num in zip(keys, nums):
            try:
                values[key] = float(num)
            except ValueError:
                break          # a row cut short
    return step, values


def tail_text(path: Path, n_bytes: int = 16384) -> str:
    """The last N_BYTES of a log that may be long (a run's md.log grows by a block per
    nstlog steps); '' if it does not exist yet."""
    try:
        with open(path, "rb") as f:
            f.seek(0, 2)
            f.seek(max(0, f.tell() - n_bytes))
            return f.read().decode(errors="replace")
    except OSError:
        return ""
