// rodsim: run a rod scene (TOML) and write the result to HDF5.
//
//   rodsim run SCENE.toml -o OUT.h5 [--quiet] [--set section.key=value ...]
//              [--checkpoint-every SECONDS] [--resume]
//   rodsim check SCENE.toml [--set ...]     validate and print the resolved scene
//   rodsim kinds                            list initial-condition kinds and parameters
//   rodsim --version                        version and git revision (as every output file records)
//
// Exit status: 0 ok, 2 bad input (scene, IC file, arguments), 3 numerical
// error (the frames written before it stay readable in OUT.h5, complete = 0),
// 1 anything else, 128 + signal number after SIGINT/SIGTERM (a checkpoint
// OUT.h5.ckpt is written first; `--resume` continues). Errors go to stderr
// prefixed "rodsim: error:". The scene and OUT are checked before any work
// (OUT: output_file.hpp).
#include <CLI/CLI.hpp>

#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <limits>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "output_file.hpp"
#include "progress.hpp"
#include "rodcore/checkpoint.hpp"
#include "rodcore/dna_units.hpp"
#include "rodcore/error.hpp"
#include "rodcore/h5_writer.hpp"
#include "rodcore/initial_conditions.hpp"  // kinds (internal: rodsim is part of rodcore)
#include "rodcore/scene_io.hpp"
#include "rodcore/simulation.hpp"
#include "rodcore/version.hpp"
#include "signals.hpp"

namespace {

int fail(int code, const std::string& msg) {
  std::cerr << "rodsim: error: " << msg << "\n";
  return code;
}

std::string num(double v) {
  if (std::isnan(v)) return "required";
  if (std::isinf(v)) return v > 0 ? "inf" : "-inf";
  std::ostringstream o;
  o << v;
  return o.str();
}

// Markdown, so that docs/scenes.md can carry it verbatim.
void print_kinds() {
  for (const auto& k : rodcore::initial_kinds()) {
    std::cout << "### `" << k.name << "`\n\n" << k.doc << "\n\n";
    if (k.numbers.empty() && k.strings.empty()) {
      std::cout << "No parameters.\n\n";
      continue;
    }
    std::cout << "| parameter | default | allowed | unit | meaning |\n|---|---|---|---|---|\n";
    for (const auto& p : k.numbers)
      std::cout << "| `" << p.name << "` | " << num(p.default_value) << " | [" << num(p.min) << ", "
                << num(p.max) << "] | " << p.unit << " | " << p.doc << " |\n";
    for (const auto& c : k.strings) {
      std::string allowed;
      for (const auto& a : c.allowed) allowed += (allowed.empty() ? "" : ", ") + ("\"" + a + "\"");
      std::cout << "| `" << c.name << "` | \"" << c.default_value << "\" | " << allowed << " | | " << c.doc
                << " |\n";
    }
    std::cout << "\n";
  }
}

// The command that continues an interrupted run (for messages).
std::string resume_command(const std::string& scene_path, const std::string& out_path,
                           const std::vector<std::string>& sets) {
  std::string cmd = "rodsim run " + scene_path + " -o " + out_path;
  for (const auto& s : sets) cmd += " --set " + s;
  return cmd + " --resume";
}

// The last line of a run: what was written, the steps, the drift, the kinetic temperature.
void print_summary(const rodcore::Scene& scene, rodcore::Simulation& sim, rodcore::H5Writer& out,
                   const rodcore::RunSummary& sum, const std::string& out_path) {
  char line[512];
  std::snprintf(line, sizeof line,
                "rodsim: wrote %s: %d frames to t = %g; %ld steps (%ld rejected), %ld RHS evaluations, "
                "%.3g s wall, energy drift %.2e (%s%s)",
                out_path.c_str(), out.frames_written(), scene.output.t_end, sum.steps, sum.rejected,
                sum.rhs_evaluations, sum.wall_seconds, sum.energy_drift, sum.method.c_str(),
                sum.reduced ? ", reduced planar system" : "");
  std::cout << line;
  if (scene.thermal.on)  // the bath exchanges energy: its kinetic temperature is the figure
    std::cout << "; kinetic kT " << sim.kinetic_kT() << " at t_end (kT " << scene.thermal.kT << ")";
  std::cout << std::endl;
}

// The output file: continued from the checkpoint (--resume, when there is one) or new, with the
// scene as written and its overrides beside the resolved one.
std::shared_ptr<rodcore::H5Writer> open_output(const rodcore::Scene& scene, rodcore::Simulation& sim,
                                               const std::string& scene_path, const std::string& out_path,
                                               const std::vector<std::string>& sets, bool quiet,
                                               bool resume) {
  namespace fs = std::filesystem;
  const std::string ckpt = rodcore::checkpoint_path(out_path);
  std::shared_ptr<rodcore::H5Writer> out;
  if (resume && fs::exists(ckpt)) {
    const rodcore::Checkpoint c = rodcore::read_checkpoint(ckpt);
    rodcore::check_checkpoint_matches(c, scene, ckpt);
    sim.resume_from(c);
    out = std::make_shared<rodcore::H5Writer>(out_path, sim, c.next_frame);
    if (!quiet)
      std::cerr << "rodsim: resuming from " << ckpt << " at t = " << c.integrator.t << " (" << c.next_frame
                << " of " << scene.output.frames << " frames written)\n";
  } else {
    if (resume && !quiet) std::cerr << "rodsim: no checkpoint " << ckpt << ": starting from t = 0\n";
    std::error_code ec;
    fs::remove(ckpt, ec);  // a stale checkpoint of an earlier run must never be paired with this output
    out = std::make_shared<rodcore::H5Writer>(out_path, sim);  // resolved method
  }
  // The scene as written, and the overrides, next to the resolved `scene`.
  {
    std::ifstream in(scene_path, std::ios::binary);
    std::ostringstream text;
    text << in.rdbuf();
    out->annotate("scene_file", text.str());
    std::string overrides;
    for (const auto& s : sets) overrides += s + "\n";
    out->annotate("scene_overrides", overrides);
  }
  return out;
}

int run(const std::string& scene_path, const std::string& out_path, const std::vector<std::string>& sets,
        bool quiet, bool resume, double checkpoint_every) {
  rodcore::Scene scene = rodcore::read_scene_file(scene_path, sets);
  rodcore::check_output_file(out_path);  // before any work: a bad -o is found now, not after the run
  if (checkpoint_every >= 0.0) scene.output.checkpoint_interval_s = checkpoint_every;
  rodcore::Simulation sim(scene);
  const std::string ckpt = rodcore::checkpoint_path(out_path);
  const std::shared_ptr<rodcore::H5Writer> out =
      open_output(scene, sim, scene_path, out_path, sets, quiet, resume);
  // The run loop's observers: the file, the checkpoints, the progress bar.
  rodcore::CheckpointSchedule schedule(scene.output.checkpoint_interval_s);
  rodcore::install_stop_signal_handlers();
  sim.add_observer(out);
  sim.add_observer(std::make_shared<rodcore::CheckpointWriter>(
      ckpt, [&] { return schedule.due(); },
      [&](const rodcore::Checkpoint& c) {
        schedule.written();
        if (int sig = rodcore::stop_signal())
          throw rodcore::Interrupted(std::string(sig == SIGINT ? "SIGINT" : "SIGTERM") +
                                         " received: stopped at t = " + num(c.integrator.t) + " with " +
                                         std::to_string(c.next_frame) + " of " +
                                         std::to_string(scene.output.frames) + " frames in " +
                                         out->partial_path() + "; checkpoint " + ckpt +
                                         ". Continue with:\n  " + resume_command(scene_path, out_path, sets),
                                     sig);
      }));
  rodcore::ProgressBar bar(!quiet && rodcore::ProgressBar::stderr_is_terminal(), stderr,
                           rodcore::dna_units::tau_ps);
  sim.add_observer(std::make_shared<rodcore::ProgressObserver>(bar));
  rodcore::RunSummary sum;
  try {
    sum = sim.run();  // finished(): the file is renamed complete, the checkpoint removed
  } catch (const rodcore::Interrupted& e) {
    bar.finish();
    std::cerr << "rodsim: " << e.what() << "\n";
    return 128 + e.signal;
  } catch (const rodcore::NumericalError& e) {
    // failed(): the file is renamed with complete = 0, the checkpoint removed
    bar.finish();
    return fail(3, std::string(e.what()) + "\nrodsim: " + std::to_string(out->frames_written()) +
                       " frame(s) written so far are in " + out_path + " (attribute complete = 0)");
  }
  bar.finish();
  if (const long jumps = out->topology_jumps(); jumps > 0)  // the closed rod passed through itself
    std::cerr << "rodsim: warning: the linking number of the closed rod changed " << jumps
              << " time(s) between frames (dataset topology/Lk, attribute topology_jumps): the rod passed "
                 "through itself or its ribbon was not resolved; self-contact ([contact], "
                 "docs/topology.md) keeps it\n";
  if (!quiet) print_summary(scene, sim, *out, sum, out_path);
  return 0;
}

// CLI::NonNegativeNumber lets NaN through (it compares) and prints DBL_MAX in full.
CLI::Validator finite_seconds_validator() {
  return CLI::Validator(
      [](std::string& text) {
        double v = 0.0;
        if (!CLI::detail::lexical_cast(text, v)) return text + ": not a number (allowed: seconds >= 0)";
        if (!std::isfinite(v)) return text + ": not a finite number (allowed: seconds >= 0)";
        if (v < 0.0) return text + ": out of range (allowed: seconds >= 0)";
        return std::string();
      },
      "SECONDS >= 0");
}

int check(const std::string& scene_path, const std::vector<std::string>& sets) {
  try {
    std::cout << rodcore::scene_to_toml(rodcore::read_scene_file(scene_path, sets));
    return 0;
  } catch (const rodcore::InputError& e) {
    return fail(2, e.what());
  } catch (const std::exception& e) {
    return fail(1, e.what());
  }
}

// The run with its exit status; the folders it made are removed again when it fails (a stop
// leaves files in them: those stay).
int run_or_fail(const std::string& scene_path, const std::string& out_path,
                const std::vector<std::string>& sets, bool quiet, bool resume, double checkpoint_every) {
  try {
    const int status = run(scene_path, out_path, sets, quiet, resume, checkpoint_every);
    if (status != 0) rodcore::remove_made_folders();
    return status;
  } catch (const rodcore::InputError& e) {
    rodcore::remove_made_folders();
    return fail(2, e.what());
  } catch (const rodcore::NumericalError& e) {
    rodcore::remove_made_folders();
    return fail(3, e.what());
  } catch (const std::exception& e) {
    rodcore::remove_made_folders();
    return fail(1, e.what());
  }
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{
      "rodsim: simulate a geometrically exact elastic rod (paper Eqs 11-14, periodic in s).\n"
      "A scene file (TOML) says what rod, which initial condition, which solver and what to\n"
      "write; see docs/scenes.md for every key and workflows/scenes/*.toml for examples.\n\n"
      "Examples:\n"
      "  rodsim run workflows/scenes/twisted_wave.toml -o wave.h5\n"
      "  rodsim run dna158.toml -o dna.h5 --set solver.rtol=1e-8 --set output.frames=101\n"
      "  rodsim check dna158.toml          # validate, print the resolved scene\n"
      "  rodsim kinds                      # initial-condition kinds and their parameters\n\n"
      "Exit status: 0 ok, 2 bad input, 3 numerical error (frames so far kept, complete = 0),\n"
      "130/143 stopped by SIGINT/SIGTERM after writing the checkpoint OUT.h5.ckpt (continue with --resume)."};
  app.require_subcommand(1);
  app.set_help_all_flag("--help-all", "Help for every subcommand");
  // The same two values every output file records (attributes rodcore_version, git_revision).
  app.set_version_flag(
      "--version",
      std::string("rodsim ") + rodcore::kRodcoreVersion + " (git revision " + rodcore::git_revision() + ")",
      "Print the version and the git revision, as every output file records them");

  const CLI::Validator finite_seconds = finite_seconds_validator();
  std::string scene_path, out_path;
  std::vector<std::string> sets;
  bool quiet = false, resume = false;
  double checkpoint_every = -1.0;  // < 0: the scene's output.checkpoint_interval_s

  auto* run_cmd = app.add_subcommand("run", "Run a scene and write OUT.h5 (time, s, fields/*, ...)");
  run_cmd->add_option("scene", scene_path, "Scene file (TOML)")->required();
  run_cmd
      ->add_option("-o,--output", out_path,
                   "Output HDF5 file (written as OUT.h5.partial until complete; an earlier HDF5 output is "
                   "replaced, any other existing file refused, a missing folder made)")
      ->required();
  run_cmd->add_option(
      "--set", sets,
      "Override a scene key, e.g. --set solver.rtol=1e-8 (repeatable; validated like the file)");
  run_cmd->add_flag("-q,--quiet", quiet, "No progress bar and no summary line");
  run_cmd
      ->add_option("--checkpoint-every", checkpoint_every,
                   "Write the checkpoint OUT.h5.ckpt every SECONDS of wall time (overrides "
                   "output.checkpoint_interval_s; 0: only on SIGINT/SIGTERM)")
      ->check(finite_seconds);
  run_cmd->add_flag(
      "--resume", resume,
      "Continue an interrupted run from OUT.h5.ckpt, appending to OUT.h5.partial (same scene and --set "
      "options; the result equals an uninterrupted run). Without a checkpoint: start from t = 0");

  auto* check_cmd =
      app.add_subcommand("check", "Validate a scene and print it resolved (all defaults filled)");
  check_cmd->add_option("scene", scene_path, "Scene file (TOML)")->required();
  check_cmd->add_option("--set", sets, "Override a scene key, as for run");

  app.add_subcommand("kinds", "List the initial-condition kinds and their parameters (Markdown)");

  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    if (e.get_exit_code() == 0) return app.exit(e);  // --help
    std::cerr << "rodsim: error: " << e.what() << "\nRun with --help for the options.\n";
    return 2;
  }

  if (app.got_subcommand("kinds")) {
    print_kinds();
    return 0;
  }
  if (app.got_subcommand("check")) return check(scene_path, sets);
  return run_or_fail(scene_path, out_path, sets, quiet, resume, checkpoint_every);
}
