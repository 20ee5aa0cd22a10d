#pragma once
// A sweep's parts: one variant of a scenario run on its own (by `dmbd simulate
// --variant`, a worker of `dmbd simulate --jobs`, or a job of `dmbd sweep plan` on any
// machine) and written as a part directory: log.bin (the variant's log, its doubles
// column after column, exact and quick to read back: a CSV's 17-digit text costs more
// to parse than the parent's merge can afford) and part.json (the scenario's name, the
// variant's name, the log's columns, units, rows and byte order, and its run facts,
// metrics.json's runs.RUN), part.json last. No experiment: the parts
// of every variant are merged by write_run (run_directory.hpp), which evaluates it over
// all of them. Logs and facts read back exactly, so the merged files are the ones a
// single run_scenario writes, wall times apart (docs/sweeps.md).
#include <string>

#include "dmbd/scenario/scenario.hpp"

namespace dmbd::scenario {

// The variant of s named `name`. Throws InputError "FILE: no variant 'NAME' (expected
// one of: ...)".
const VariantSetup& find_variant(const Scenario& s, const std::string& name);

// Compiles the generated code of every controller of s that runs as its generated code
// (software in the loop), several at once, as run_scenario does first: processes forked
// afterwards to run variants find the objects built and loaded.
void build_controllers(const Scenario& s);

// r, a run of a variant of s, written into DIR (created if missing): DIR/log.bin, then
// DIR/part.json. Throws OutputError for a folder or file that cannot be written.
void write_part(const Scenario& s, const sim::VariantResult& r, const std::string& dir);

// The part of variant v of s read back from DIR: its log and run facts (axes from v).
// Throws InputError naming the file: "DIR/part.json: missing (the run of variant 'V'
// did not finish)", a part of another scenario or variant, a malformed file, a log.bin
// of another size than part.json says or from a machine of the other byte order.
sim::VariantResult read_part(const Scenario& s, const VariantSetup& v, const std::string& dir);

}  // namespace dmbd::scenario
