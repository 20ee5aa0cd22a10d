#pragma once
// Writing outputs so that an interrupted or failed run never leaves a half-written file:
// the bytes go to "<path>.tmp", which is then renamed over the path.
#include <string>
#include <vector>

namespace dmbd {

// Throws OutputError "cannot write 'PATH': REASON" (the .tmp file is removed).
void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes);
void write_file_atomic(const std::string& path, const std::string& text);

// The whole file. Throws InputError "PATH: cannot read: REASON" (a missing file, a
// directory, no permission).
std::string read_file(const std::string& path);

}  // namespace dmbd
