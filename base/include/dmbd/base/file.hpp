#pragma once
// Files: a user's file read whole (with the system's reason when it cannot be), and
// outputs written so that an interrupted or failed run never leaves a half-written
// file: the bytes go to "<path>.tmp", which is then renamed over the path.
#include <optional>
#include <string>
#include <vector>

namespace dmbd {

// Throws OutputError "cannot write 'PATH': REASON" (the .tmp file is removed).
void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes);
void write_file_atomic(const std::string& path, const std::string& text);

// The whole file. Throws InputError "PATH: cannot read: REASON" (a missing file, a
// directory, no permission).
std::string read_file(const std::string& path);

// The same without throwing: the bytes in `bytes` and nullopt, or why the file cannot
// be read ("it is a directory", "No such file or directory": the system's reason).
std::optional<std::string> try_read_file(const std::string& path, std::string& bytes);

}  // namespace dmbd
