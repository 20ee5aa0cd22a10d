#pragma once
// C++ source compiled by the system compiler into a shared object
// while the program runs, and loaded (software in the loop: sil_controller.hpp).
//
// The compiler is $CXX when set (its words split at blanks, started without a shell:
// base/process.hpp), else `c++`, with
// kSharedObjectFlags. Builds are cached for the life of the process by their exact text
// (compiler, flags and every file), so identical sources compile once; sources not yet
// built are compiled several at once (one compiler per core). Each build happens in its
// own folder under the system's temporary folder, removed when its object is unloaded
// (at the latest when the process exits); a build that fails keeps its folder for its
// compile.log.
#include <memory>
#include <string>
#include <utility>
#include <vector>

namespace dmbd::sim {

// C++11 as the generated code promises; position-independent, symbols hidden but the
// ones marked to be loaded (so that two objects built from programs of the same name
// never resolve to each other's code); warnings are errors; no contraction of a
// multiply and an add into one fused operation (the interpreter rounds both).
constexpr const char* kSharedObjectFlags =
    "-std=c++11 -O2 -fPIC -shared -fvisibility=hidden -fno-exceptions -fno-rtti -ffp-contract=off -Wall -Wextra -Werror";

// The system compiler a shared object is built with.
struct Compiler {
  std::string command;  // $CXX or "c++"
  std::string version;  // the first line of `command --version` ("" when it gives none)
  std::string flags;    // kSharedObjectFlags
};
// The compiler builds use now (its version asked once per command).
Compiler shared_object_compiler();

// A loaded shared object (dlopen, local symbols); closed when the last owner goes, and
// then its build folder removed. The file stays while it is loaded: the loader knows a
// loaded object by its device and inode, and a deleted file's inode may be given to the
// next object built.
class SharedObject {
 public:
  // Throws InputError with the loader's reason (which names the file).
  SharedObject(const std::string& path, const std::string& build_folder);
  ~SharedObject();
  SharedObject(const SharedObject&) = delete;
  SharedObject& operator=(const SharedObject&) = delete;
  // The address of an exported symbol; nullptr when there is none.
  void* symbol(const char* name) const;

 private:
  void* handle_ = nullptr;
  std::string folder_;
};

// What a shared object is built from: its files, written side by side.
struct SharedObjectSource {
  std::string name;                                         // names the build folder and the object
  std::vector<std::pair<std::string, std::string>> files;  // file name -> text, written side by side
  std::string main;                                         // the file compiled (one of `files`)
};

// A shared object built (or why not).
struct SharedObjectBuild {
  std::shared_ptr<const SharedObject> object;  // null when it did not build
  Compiler compiler;      // what built it
  std::string error;      // why not, a clause: "does not compile (COMMAND): the compiler's first
                          // error line (full log: PATH)" or "does not load: the loader's reason"
  std::string key;        // 16 hex digits naming the source's text (FNV-1a of compiler, flags, files)
  double compile_s = 0;   // wall time of its compilation in this process
  bool cached = false;    // built earlier in this process (compile_s is that build's)
};

// Each source built (or taken from the cache), in order. Nothing is thrown: a folder
// that cannot be written, a compiler that fails and an object that does not load are
// each in their build's `error` (and cached too: the same source is not tried again).
std::vector<SharedObjectBuild> build_shared_objects(const std::vector<SharedObjectSource>& sources);

}  // namespace dmbd::sim
