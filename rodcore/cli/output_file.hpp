// rodsim's output file, checked before any work (docs/reliability.md, "Bad input"): the same
// rules as the dnarod commands' outputs (workflows/validate.py), so one rule holds everywhere.
//
//   * OUT must name a file: an existing folder, FIFO, device or socket is refused, and so is an
//     existing file that is not HDF5 (the scene itself, say). An existing HDF5 file, the output
//     of an earlier run, is replaced when the run ends, as before; `--resume` continues
//     OUT.partial in place.
//   * A missing parent folder is made, like `mkdir -p`; the folders made are removed again if
//     rodsim then fails and they are still empty (remove_made_folders).
//   * The folder must take a new file: tried by writing one, not read from permission bits (root
//     may write almost anywhere, but not under a regular file or under /proc).
//
// Each failure is an InputError (exit 2) naming "-o OUT" and what is allowed.
#pragma once
#include <string>

namespace rodcore {

void check_output_file(const std::string& out_path);

// After a failure: remove the folders check_output_file made that are still empty, deepest first.
void remove_made_folders();

}  // namespace rodcore
