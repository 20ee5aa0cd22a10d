#pragma once
// Files: a user's file read whole but bounded (with the system's reason when it cannot
// be: any kind of file, so /dev/stdin and a pipe work, but /dev/zero stops at once), and
// outputs written so that an interrupted or failed run never leaves a half-written
// file: the bytes go to "<path>.tmp", which is then renamed over the path.
#include <cstddef>
#include <optional>
#include <string>
#include <vector>

namespace dmbd {

// Throws OutputError "cannot write 'PATH': REASON" (the .tmp file is removed).
void write_file_atomic(const std::string& path, const std::vector<unsigned char>& bytes);
void write_file_atomic(const std::string& path, const std::string& text);

// The most a user's file is read: a model, diagram, scenario or JSON file (256 MiB), and
// a run's data (log.csv, a sweep part's log.bin: 2 GiB). Reading stops one chunk past it.
constexpr std::size_t kMaxInputFileBytes = std::size_t{256} << 20;
constexpr std::size_t kMaxDataFileBytes = std::size_t{2} << 30;

// The whole file, read in chunks, at most `limit` bytes. Throws InputError
// "PATH: cannot read: REASON" (a missing file, a directory, no permission, too large).
std::string read_file(const std::string& path, std::size_t limit = kMaxInputFileBytes);

// The same without throwing: the bytes in `bytes` and nullopt, or why the file cannot
// be read ("it is a directory", "No such file or directory": the system's reason;
// "larger than the limit of 268435456 bytes" as soon as it is).
std::optional<std::string> try_read_file(const std::string& path, std::string& bytes, std::size_t limit = kMaxInputFileBytes);

// A text file (every file a parser reads: YAML, URDF, CSV, JSON): as try_read_file, but
// reading stops at the first byte that is not UTF-8 text (not_text's rule, text.hpp):
// `text` then ends with that byte, for the parser's not_text check to name it at its
// line and column ("the file is not text: byte 1 is 0x00, a control character ...").
std::optional<std::string> try_read_text_file(const std::string& path, std::string& text, std::size_t limit = kMaxInputFileBytes);

// The same, throwing InputError "PATH: cannot read: REASON", or not_text's located
// message "PATH:LINE:COL: the file is not text: byte N is 0xHH, ..." (for readers
// without a check of their own: CSV, JSON).
std::string read_text_file(const std::string& path, std::size_t limit = kMaxInputFileBytes);

}  // namespace dmbd
