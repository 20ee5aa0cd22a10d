#pragma once
// One `dmbd` subcommand: it adds itself and its options to the application, and runs
// when the command line chose it. Commands do not catch errors: main() (apps/dmbd.cpp)
// has the one ladder that turns an InputError into one line and exit status 2, and
// anything else into an internal error (exit 1).
#include <CLI/CLI.hpp>

#include <string>

namespace dmbd::apps {

class Command {
 public:
  Command(CLI::App& app, const std::string& name, const std::string& description)
      : cmd_(app.add_subcommand(name, description)) {}
  virtual ~Command() = default;
  Command(const Command&) = delete;  // CLI11 holds pointers to the options' variables
  Command& operator=(const Command&) = delete;

  // Whether the command line chose this command (valid after app.parse).
  bool selected() const { return cmd_->parsed(); }
  // Runs it; returns the exit status.
  virtual int run() = 0;

 protected:
  CLI::App* cmd_;
};

}  // namespace dmbd::apps
