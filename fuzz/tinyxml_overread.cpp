// The verdict on the URDF fuzzer's unreproducible heap-buffer-overflows (issue 13,
// item 12): TinyXML 2.6.2 (used by urdfdom and by model/src/urdf_loader.cpp) reads
// past the terminator of the text it parses when a UTF-8 lead byte announces more
// bytes than remain. GetChar() copies up to the terminator but returns p + length,
// so the parser goes on reading whatever follows the string.
//
// Here the text ends exactly at a page boundary followed by an unreadable page, so a
// read past the terminator is a SIGSEGV, every time (exit 139). Built by scripts/fuzz
// --build as build-fuzz/fuzz/tinyxml_overread; parse_urdf now refuses such text first.
#include <sys/mman.h>
#include <unistd.h>

#include <cstdio>
#include <cstring>

#include <tinyxml.h>

int main() {
  const long page = sysconf(_SC_PAGESIZE);
  void* map = mmap(nullptr, 2 * static_cast<size_t>(page), PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS, -1, 0);
  if (map == MAP_FAILED) return 2;
  char* mem = static_cast<char*>(map);
  if (mprotect(mem + page, static_cast<size_t>(page), PROT_NONE) != 0) return 2;
  const char text[] = "<robot name=\"r\">\xF0";  // a 4-byte UTF-8 sequence cut short by the end
  char* start = mem + page - sizeof text;         // the terminator is the page's last byte
  std::memcpy(start, text, sizeof text);
  std::printf("TinyXML parses %zu bytes that end just before an unreadable page...\n", sizeof text - 1);
  std::fflush(stdout);
  TiXmlDocument doc;
  doc.Parse(start, nullptr, TIXML_ENCODING_UTF8);
  std::printf("it stayed inside the text (%s)\n", doc.Error() ? doc.ErrorDesc() : "no error");
  return 0;
}
