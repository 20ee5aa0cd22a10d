// The replay page's copy of three.js (Debian's libjs-three, r111): the library, its orbit
// controls and its licence, copied beside the page so that it opens offline.
#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "dmbd/base/error.hpp"
#include "dmbd/base/file.hpp"
#include "dmbd/viz/replay.hpp"

namespace dmbd::viz {

namespace fs = std::filesystem;

namespace {

// three.js's licence (its LICENSE file), written where Debian's copyright file, which
// carries it, is absent (an image installed without /usr/share/doc).
constexpr const char* kMitLicence = R"(three.js (https://threejs.org), revision 111, as Debian's libjs-three ships it.

The MIT License

Copyright (c) 2010-2019 three.js authors

Permission is hereby granted, free of charge, to any person obtaining a copy
of this software and associated documentation files (the "Software"), to deal
in the Software without restriction, including without limitation the rights
to use, copy, modify, merge, publish, distribute, sublicense, and/or sell
copies of the Software, and to permit persons to whom the Software is
furnished to do so, subject to the following conditions:

The above copyright notice and this permission notice shall be included in
all copies or substantial portions of the Software.

THE SOFTWARE IS PROVIDED "AS IS", WITHOUT WARRANTY OF ANY KIND, EXPRESS OR
IMPLIED, INCLUDING BUT NOT LIMITED TO THE WARRANTIES OF MERCHANTABILITY,
FITNESS FOR A PARTICULAR PURPOSE AND NONINFRINGEMENT. IN NO EVENT SHALL THE
AUTHORS OR COPYRIGHT HOLDERS BE LIABLE FOR ANY CLAIM, DAMAGES OR OTHER
LIABILITY, WHETHER IN AN ACTION OF CONTRACT, TORT OR OTHERWISE, ARISING FROM,
OUT OF OR IN CONNECTION WITH THE SOFTWARE OR THE USE OR OTHER DEALINGS IN
THE SOFTWARE.
)";

constexpr const char* kDebianCopyright = "/usr/share/doc/libjs-three/copyright";

std::string library_file(const std::string& path) {
  std::string bytes;
  if (const auto why = try_read_file(path, bytes))
    throw InputError(path + ": cannot read: " + *why + " (three.js for the report's 3-D replay: install Debian's libjs-three, "
                     "or set DMBD_THREE_JS_DIR)");
  return bytes;
}

}  // namespace

std::string three_js_dir() {
  const char* dir = std::getenv("DMBD_THREE_JS_DIR");
  return dir && *dir ? dir : "/usr/share/javascript/three";
}

std::vector<std::string> copy_three_js(const std::string& folder) {
  const fs::path from(three_js_dir()), to(folder);
  const std::string three = library_file((from / "three.min.js").string());
  const std::string orbit = library_file((from / "examples/js/controls/OrbitControls.js").string());
  std::string licence;
  if (try_read_file(kDebianCopyright, licence)) licence = kMitLicence;  // a reason returned: not readable
  write_file_atomic((to / "three.min.js").string(), three);
  write_file_atomic((to / "OrbitControls.js").string(), orbit);
  write_file_atomic((to / "three.js-LICENSE.txt").string(), licence);
  return {"three.min.js", "OrbitControls.js", "three.js-LICENSE.txt"};
}

}  // namespace dmbd::viz
