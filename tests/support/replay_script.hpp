#pragma once
// Reads a 3-D replay's script back (viz/replay.hpp): the table and key it files its JSON
// under, and its base64 arrays decoded here, with a decoder of the test's own (shared by
// tests/viz/test_replay.cpp and the report's replay tests).
#include <cstdint>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace dmbd::test::replay {

struct Script {
  std::string table, key;  // "scenes" or "tracks"; the file's path as the page names it
  nlohmann::json value;
};

// Throws std::runtime_error unless the text is one statement
// "(window.dmbdReplay = window.dmbdReplay || {scenes: {}, tracks: {}}).TABLE[KEY] = JSON;\n".
inline Script parse(const std::string& text) {
  const std::string head = "(window.dmbdReplay = window.dmbdReplay || {scenes: {}, tracks: {}}).";
  if (text.compare(0, head.size(), head) != 0) throw std::runtime_error("not a replay script: " + text.substr(0, 80));
  const std::size_t open = text.find('[', head.size()), eq = text.find("] = ", head.size());
  if (open == std::string::npos || eq == std::string::npos || text.size() < 2 || text.substr(text.size() - 2) != ";\n")
    throw std::runtime_error("not a replay script: " + text.substr(0, 80));
  Script s;
  s.table = text.substr(head.size(), open - head.size());
  s.key = nlohmann::json::parse(text.substr(open + 1, eq - open - 1)).get<std::string>();
  s.value = nlohmann::json::parse(text.substr(eq + 4, text.size() - eq - 6));
  return s;
}

// RFC 4648 base64 with '=' padding; throws on any other character or a bad length.
inline std::vector<unsigned char> decode_base64(const std::string& b64) {
  if (b64.size() % 4 != 0) throw std::runtime_error("base64 length not a multiple of 4");
  auto value = [](char c) -> int {
    if (c >= 'A' && c <= 'Z') return c - 'A';
    if (c >= 'a' && c <= 'z') return c - 'a' + 26;
    if (c >= '0' && c <= '9') return c - '0' + 52;
    if (c == '+') return 62;
    if (c == '/') return 63;
    throw std::runtime_error(std::string("not a base64 digit: ") + c);
  };
  std::vector<unsigned char> out;
  for (std::size_t i = 0; i < b64.size(); i += 4) {
    const int pad = (b64[i + 3] == '=') + (b64[i + 2] == '=');
    if (pad > 0 && i + 4 != b64.size()) throw std::runtime_error("base64 padding inside the text");
    std::uint32_t v = 0;
    for (int k = 0; k < 4; ++k) v = (v << 6) | (k >= 4 - pad ? 0u : static_cast<std::uint32_t>(value(b64[i + k])));
    for (int k = 0; k < 3 - pad; ++k) out.push_back(static_cast<unsigned char>((v >> (16 - 8 * k)) & 0xff));
  }
  return out;
}

// Little-endian float32 values.
inline std::vector<float> floats(const std::string& b64) {
  const std::vector<unsigned char> b = decode_base64(b64);
  if (b.size() % 4 != 0) throw std::runtime_error("float32 data not a multiple of 4 bytes");
  std::vector<float> out(b.size() / 4);
  for (std::size_t i = 0; i < out.size(); ++i) {
    const std::uint32_t bits = b[4 * i] | (b[4 * i + 1] << 8) | (b[4 * i + 2] << 16) | (std::uint32_t{b[4 * i + 3]} << 24);
    std::memcpy(&out[i], &bits, 4);
  }
  return out;
}

// Little-endian unsigned integers of `bytes` (2 or 4) bytes each.
inline std::vector<std::uint32_t> uints(const std::string& b64, int bytes) {
  const std::vector<unsigned char> b = decode_base64(b64);
  std::vector<std::uint32_t> out;
  for (std::size_t i = 0; i + static_cast<std::size_t>(bytes) <= b.size(); i += static_cast<std::size_t>(bytes)) {
    std::uint32_t v = 0;
    for (int k = bytes - 1; k >= 0; --k) v = (v << 8) | b[i + static_cast<std::size_t>(k)];
    out.push_back(v);
  }
  return out;
}

}  // namespace dmbd::test::replay
