// The `dmbd` command line: the subcommands (one file each: apps/*_cmd.cpp), the words
// CLI11 does not know, and the one place where errors become messages and exit codes.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <iostream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include "analyze_cmd.hpp"
#include "codegen_cmd.hpp"
#include "dmbd/base/error.hpp"
#include "dmbd/base/temporaries.hpp"
#include "dmbd/diagrams/diagram.hpp"
#include "dmbd/version.hpp"
#include "draw_cmd.hpp"
#include "model_cmd.hpp"
#include "report_cmd.hpp"
#include "dmbd/base/strings.hpp"
#include "simulate_cmd.hpp"
#include "sweep_cmd.hpp"
#include "tune_cmd.hpp"

namespace {


// "dmbd analize": CLI11 would say only that a subcommand is required. One line naming
// the word, the commands and the closest one; empty when the word is a command.
std::string unknown_command(CLI::App& app, int argc, char** argv) {
  if (argc < 2 || argv[1][0] == '-') return "";
  const std::string word = argv[1];
  std::string names, closest;
  std::size_t best = std::string::npos;
  for (const CLI::App* c : app.get_subcommands([](CLI::App*) { return true; })) {
    if (c->get_name() == word) return "";
    names += (names.empty() ? "" : ", ") + c->get_name();
    const std::size_t d = dmbd::edit_distance(word, c->get_name());
    if (d < best) best = d, closest = c->get_name();
  }
  return "dmbd: error: unknown command '" + word + "' (expected one of: " + names + ")" +
         (best <= 2 ? "; did you mean '" + closest + "'?" : "");
}

std::string one_line(std::string msg) {
  std::replace(msg.begin(), msg.end(), '\n', ' ');
  return msg;
}

// The error contract (docs/architecture.md): a mistake in what the user gave (an
// InputError from any module, an output that cannot be written) is one line on stderr
// and exit 2 (every problem of a diagram, a scenario or an actuator table, one line
// each); anything else is a defect of the tool, exit 1.
int run_command(dmbd::apps::Command& command) {
  try {
    return command.run();
  } catch (const dmbd::diagrams::DiagramError& e) {
    for (const auto& d : e.diagnostics()) std::cerr << one_line(d.str()) << "\n";
  } catch (const dmbd::InputError& e) {
    std::istringstream problems(e.what());  // the located readers give one problem a line
    for (std::string line; std::getline(problems, line);) std::cerr << "dmbd: error: " << line << "\n";
  } catch (const std::exception& e) {
    std::cerr << "dmbd: internal error: " << one_line(e.what()) << "\n";
    return 1;
  }
  return 2;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"draco-mbd: model-based design for legged robots (block diagrams, analysis, code generation, "
               "simulation of robots on their actuators)",
               "dmbd"};
  app.set_version_flag("--version", std::string("dmbd ") + dmbd::kVersion);
  app.require_subcommand(1);
  std::vector<std::unique_ptr<dmbd::apps::Command>> commands;
  commands.push_back(std::make_unique<dmbd::apps::AnalyzeCommand>(app));
  commands.push_back(std::make_unique<dmbd::apps::DrawCommand>(app));
  commands.push_back(std::make_unique<dmbd::apps::TuneCommand>(app));
  commands.push_back(std::make_unique<dmbd::apps::CodegenCommand>(app));
  commands.push_back(std::make_unique<dmbd::apps::ModelCommand>(app));
  commands.push_back(std::make_unique<dmbd::apps::SimulateCommand>(app));
  commands.push_back(std::make_unique<dmbd::apps::ReportCommand>(app));
  commands.push_back(std::make_unique<dmbd::apps::SweepCommand>(app));

  if (const std::string unknown = unknown_command(app, argc, argv); !unknown.empty()) {
    std::cerr << unknown << "\n";
    return 2;
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForAllHelp& e) {
    return app.exit(e);
  } catch (const CLI::CallForVersion& e) {
    return app.exit(e);
  } catch (const CLI::ParseError& e) {
    std::cerr << "dmbd: error: " << one_line(e.what()) << " (see dmbd --help)\n";
    return 2;
  }
  dmbd::remove_temporaries_on_signals();  // an interrupted run leaves no .tmp file
  for (const auto& c : commands)
    if (c->selected()) return run_command(*c);
  return 0;
}
