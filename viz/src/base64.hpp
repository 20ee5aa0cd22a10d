#pragma once
// Internal to viz/: base64 text of bytes, and little-endian float32 / integer arrays as
// base64 (the replay's data files, replay_data.cpp).
#include <cstddef>
#include <cstdint>
#include <string>
#include <vector>

namespace dmbd::viz::detail {

// Standard base64 (RFC 4648, '=' padding). Written here: none of viz's libraries
// (OpenCV, FFmpeg, libdeflate) offers it in its public interface, and it is 20 lines.
std::string base64(const unsigned char* data, std::size_t bytes);

// The values as float32, little-endian, in base64 (a NaN stays a NaN).
std::string base64_float32(const std::vector<float>& values);
// The values as unsigned integers of `bytes` (2 or 4) bytes each, little-endian, in base64.
std::string base64_uint(const std::vector<std::uint32_t>& values, int bytes);

}  // namespace dmbd::viz::detail
