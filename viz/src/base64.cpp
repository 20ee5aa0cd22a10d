// Base64 text of little-endian number arrays (the replay's data files).
#include "base64.hpp"

#include <cstring>

namespace dmbd::viz::detail {

std::string base64(const unsigned char* data, std::size_t bytes) {
  static constexpr char kDigits[] = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  out.reserve((bytes + 2) / 3 * 4);
  std::size_t i = 0;
  for (; i + 3 <= bytes; i += 3) {
    const std::uint32_t v = (std::uint32_t{data[i]} << 16) | (std::uint32_t{data[i + 1]} << 8) | data[i + 2];
    for (int s : {18, 12, 6, 0}) out += kDigits[(v >> s) & 63];
  }
  if (const std::size_t rest = bytes - i; rest > 0) {
    const std::uint32_t v = (std::uint32_t{data[i]} << 16) | (rest > 1 ? std::uint32_t{data[i + 1]} << 8 : 0u);
    out += kDigits[(v >> 18) & 63];
    out += kDigits[(v >> 12) & 63];
    out += rest > 1 ? kDigits[(v >> 6) & 63] : '=';
    out += '=';
  }
  return out;
}

namespace {

void put_le(std::vector<unsigned char>& out, std::uint32_t v, int bytes) {
  for (int b = 0; b < bytes; ++b) out.push_back(static_cast<unsigned char>((v >> (8 * b)) & 0xff));
}

}  // namespace

std::string base64_float32(const std::vector<float>& values) {
  static_assert(sizeof(float) == 4, "float is IEEE 754 binary32");
  std::vector<unsigned char> bytes;
  bytes.reserve(4 * values.size());
  for (const float f : values) {
    std::uint32_t bits;
    std::memcpy(&bits, &f, 4);
    put_le(bytes, bits, 4);
  }
  return base64(bytes.data(), bytes.size());
}

std::string base64_uint(const std::vector<std::uint32_t>& values, int bytes_each) {
  std::vector<unsigned char> bytes;
  bytes.reserve(static_cast<std::size_t>(bytes_each) * values.size());
  for (const std::uint32_t v : values) put_le(bytes, v, bytes_each);
  return base64(bytes.data(), bytes.size());
}

}  // namespace dmbd::viz::detail
