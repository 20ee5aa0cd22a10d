// Compiling C++ source into a shared object at run time and loading it (sil_build.hpp).
#include "dmbd/sim/shared_object.hpp"

#include <dlfcn.h>
#include <unistd.h>

#include <algorithm>
#include <atomic>
#include <chrono>
#include <condition_variable>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <map>
#include <mutex>
#include <set>
#include <thread>

#include <fmt/format.h>

#include "dmbd/base/error.hpp"
#include "dmbd/base/process.hpp"

namespace dmbd::sim {

namespace fs = std::filesystem;

namespace {

// The process's builds by their exact text, the ones being built, and each compiler
// command's version line.
struct Cache {
  std::mutex mutex;
  std::condition_variable built;
  std::map<std::string, SharedObjectBuild> builds;
  std::set<std::string> pending;
  std::map<std::string, std::string> versions;
};

Cache& cache() {
  static Cache c;
  return c;
}

std::string fnv1a_hex(const std::string& text) {
  std::uint64_t h = 14695981039346656037ull;
  for (unsigned char ch : text) h = (h ^ ch) * 1099511628211ull;
  return fmt::format("{:016x}", h);
}

// The first line of what a program writes ("" when it writes nothing or does not run).
std::string first_output_line(const std::vector<std::string>& argv) {
  const std::string out = program_output(argv);
  return out.substr(0, out.find('\n'));
}

// What a compiler's log says went wrong: its first line that mentions an error, else
// its first line, else the exit status.
std::string compiler_complaint(const fs::path& log, int status) {
  std::ifstream in(log);
  std::string line, first;
  while (std::getline(in, line)) {
    if (line.find("error") != std::string::npos) return line;
    if (first.empty()) first = line;
  }
  return first.empty() ? fmt::format("it failed without a message (exit status {})", status) : first;
}

std::vector<std::string> with_version_flag(const std::string& command) {
  std::vector<std::string> argv = command_words(command);
  argv.push_back("--version");
  return argv;
}

// The text a build is known by: compiler, flags and every file.
std::string build_text(const Compiler& c, const SharedObjectSource& s) {
  std::string t = c.command + '\0' + c.flags + '\0' + s.main + '\0';
  for (const auto& [name, text] : s.files) t += name + '\0' + text + '\0';
  return t;
}

// One build in its own folder; every failure in the result's `error`.
SharedObjectBuild compile(const Compiler& c, const SharedObjectSource& s, const std::string& key) {
  SharedObjectBuild b;
  b.compiler = c;
  b.key = key;
  std::error_code ec;
  const fs::path dir = fs::temp_directory_path(ec) / fmt::format("dmbd-sil-{}-{}-{}", ::getpid(), s.name, key);
  if (!ec) fs::create_directories(dir, ec);
  if (ec) {
    b.error = fmt::format("cannot be built: no folder '{}': {}", dir.string(), ec.message());
    return b;
  }
  for (const auto& [name, text] : s.files) {
    std::ofstream f(dir / name, std::ios::binary);
    f << text;
    if (!f.flush()) {
      b.error = fmt::format("cannot be built: cannot write '{}'", (dir / name).string());
      return b;
    }
  }
  const fs::path object = dir / ("lib" + s.name + ".so"), log = dir / "compile.log";
  std::vector<std::string> argv = command_words(c.command);
  for (const std::string& flag : command_words(c.flags)) argv.push_back(flag);
  for (const std::string& word : {std::string("-o"), object.string(), (dir / s.main).string()}) argv.push_back(word);
  const auto t0 = std::chrono::steady_clock::now();
  const ProgramRun run = run_program(argv, log.string(), log.string());
  b.compile_s = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  if (!run.ok()) {
    b.error = fmt::format("does not compile ({}): {} (full log: {})", c.command,
                          run.exit_code < 0 ? run.why : compiler_complaint(log, run.exit_code), log.string());
    return b;
  }
  try {
    b.object = std::make_shared<const SharedObject>(object.string(), dir.string());
  } catch (const InputError& e) {
    b.error = std::string("does not load: ") + e.what();
  }
  return b;
}

}  // namespace

Compiler shared_object_compiler() {
  Compiler c;
  const char* cxx = std::getenv("CXX");
  c.command = cxx && *cxx ? cxx : "c++";
  c.flags = kSharedObjectFlags;
  Cache& k = cache();
  std::lock_guard<std::mutex> lock(k.mutex);
  const auto it = k.versions.find(c.command);
  c.version = it != k.versions.end() ? it->second : (k.versions[c.command] = first_output_line(with_version_flag(c.command)));
  return c;
}

SharedObject::SharedObject(const std::string& path, const std::string& build_folder)
    : handle_(::dlopen(path.c_str(), RTLD_NOW | RTLD_LOCAL)), folder_(build_folder) {
  if (!handle_) {
    const char* why = ::dlerror();
    throw InputError(why ? why : "cannot load '" + path + "'");
  }
}

SharedObject::~SharedObject() {
  ::dlclose(handle_);
  std::error_code ec;
  fs::remove_all(folder_, ec);
}

void* SharedObject::symbol(const char* name) const { return ::dlsym(handle_, name); }

std::vector<SharedObjectBuild> build_shared_objects(const std::vector<SharedObjectSource>& sources) {
  const Compiler c = shared_object_compiler();
  Cache& k = cache();
  // The sources this process has neither built nor is building, each once.
  std::vector<std::string> texts;
  std::vector<std::size_t> todo;  // index into sources of each new text's first source
  {
    std::lock_guard<std::mutex> lock(k.mutex);
    for (std::size_t i = 0; i < sources.size(); ++i) {
      texts.push_back(build_text(c, sources[i]));
      if (!k.builds.count(texts[i]) && k.pending.insert(texts[i]).second) todo.push_back(i);
    }
  }
  // One compiler per core at a time, each in its own thread.
  std::vector<SharedObjectBuild> built(todo.size());
  std::atomic<std::size_t> next{0};
  auto worker = [&] {
    for (std::size_t j = next++; j < todo.size(); j = next++) {
      const std::string key = fnv1a_hex(texts[todo[j]]);
      try {
        built[j] = compile(c, sources[todo[j]], key);
      } catch (const std::exception& e) {  // out of memory, a path the system refuses
        built[j].compiler = c;
        built[j].key = key;
        built[j].error = std::string("cannot be built: ") + e.what();
      }
    }
  };
  const std::size_t n = std::min<std::size_t>(todo.size(), std::max(1u, std::thread::hardware_concurrency()));
  std::vector<std::thread> threads;
  for (std::size_t t = 1; t < n; ++t) threads.emplace_back(worker);
  worker();
  for (auto& t : threads) t.join();

  std::unique_lock<std::mutex> lock(k.mutex);
  for (std::size_t j = 0; j < todo.size(); ++j) {
    k.builds.emplace(texts[todo[j]], std::move(built[j]));
    k.pending.erase(texts[todo[j]]);
  }
  k.built.notify_all();
  // Sources another thread was building.
  k.built.wait(lock, [&] { return std::all_of(texts.begin(), texts.end(), [&](const auto& t) { return k.builds.count(t) > 0; }); });
  std::vector<SharedObjectBuild> out;
  for (std::size_t i = 0; i < sources.size(); ++i) {
    out.push_back(k.builds.at(texts[i]));
    out.back().cached = std::find(todo.begin(), todo.end(), i) == todo.end();
  }
  return out;
}

}  // namespace dmbd::sim
