#pragma once
// VTK XML files as VTK writes them, in every encoding (ascii, base64 "binary", appended raw
// or base64, zlib blocks, 32- or 64-bit headers, either byte order), for the readers' tests
// (test_vtk_io.cpp, test_vtk_formats.cpp).
#include <zlib.h>

#include <algorithm>
#include <cstdint>
#include <cstring>
#include <string>
#include <vector>

namespace sciray_test {

inline std::string base64(const std::vector<std::uint8_t>& bytes) {
  static const char* table = "ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
  std::string out;
  for (std::size_t i = 0; i < bytes.size(); i += 3) {
    const std::uint32_t b = static_cast<std::uint32_t>(bytes[i]) << 16 |
                            (i + 1 < bytes.size() ? static_cast<std::uint32_t>(bytes[i + 1]) << 8 : 0u) |
                            (i + 2 < bytes.size() ? bytes[i + 2] : 0u);
    out += table[b >> 18 & 63];
    out += table[b >> 12 & 63];
    out += i + 1 < bytes.size() ? table[b >> 6 & 63] : '=';
    out += i + 2 < bytes.size() ? table[b & 63] : '=';
  }
  return out;
}

template <class T>
std::vector<std::uint8_t> bytes_of(const std::vector<T>& values, bool big_endian) {
  std::vector<std::uint8_t> raw(values.size() * sizeof(T));
  std::memcpy(raw.data(), values.data(), raw.size());
  if (big_endian)
    for (std::size_t i = 0; i < raw.size(); i += sizeof(T)) std::reverse(raw.begin() + i, raw.begin() + i + sizeof(T));
  return raw;
}

/// How a VTK XML test file encodes its arrays.
struct Encoding {
  std::string format;  // ascii, binary, appended
  bool appended_base64 = false, compressed = false, header64 = false, big_endian = false;
};

inline std::string describe(const Encoding& e) {
  return e.format + (e.appended_base64 ? " base64" : "") + (e.compressed ? ", zlib" : "") +
         (e.header64 ? ", UInt64 headers" : "") + (e.big_endian ? ", big-endian" : "");
}

const Encoding xml_encodings[] = {{"ascii"},
                                  {"binary"},
                                  {"binary", false, true},
                                  {"binary", false, true, true},
                                  {"appended"},
                                  {"appended", false, true, true},
                                  {"appended", true},
                                  {"appended", true, true},
                                  {"binary", false, false, true, true},
                                  {"appended", false, true, false, true}};

/// DataArray elements as VTK writes them with an encoding; appended ones gather their
/// data for file() to put after the XML.
struct XmlWriter {
  Encoding e;
  std::string appended;

  std::vector<std::uint8_t> word(std::uint64_t n) const {
    std::vector<std::uint8_t> w(e.header64 ? 8 : 4);
    for (std::size_t k = 0; k < w.size(); ++k)
      w[e.big_endian ? w.size() - 1 - k : k] = static_cast<std::uint8_t>(n >> (8 * k));
    return w;
  }

  template <class T>
  std::string array(const std::string& name, const std::string& type, int components, const std::vector<T>& values) {
    std::string head = "<DataArray type=\"" + type + "\" Name=\"" + name + "\" NumberOfComponents=\"" +
                       std::to_string(components) + "\" format=\"" + e.format + "\"";
    if (e.format == "ascii") {
      std::string body;
      for (const auto& x : values) body += std::to_string(+x) + " ";
      return head + ">\n" + body + "\n</DataArray>\n";
    }
    const std::vector<std::uint8_t> raw = bytes_of(values, e.big_endian);
    std::vector<std::uint8_t> header, data;
    if (e.compressed) {
      uLongf size = compressBound(static_cast<uLong>(raw.size()));
      data.resize(size);
      compress(data.data(), &size, raw.data(), static_cast<uLong>(raw.size()));
      data.resize(size);
      for (std::uint64_t w :
           {std::uint64_t{1}, std::uint64_t{raw.size()}, std::uint64_t{raw.size()}, std::uint64_t{size}}) {
        const auto b = word(w);
        header.insert(header.end(), b.begin(), b.end());
      }
    } else {
      header = word(raw.size());
      data = raw;
    }
    std::vector<std::uint8_t> together = header;
    together.insert(together.end(), data.begin(), data.end());
    // Compressed arrays encode the header apart from the blocks, as VTK does.
    const std::string encoded = e.compressed ? base64(header) + base64(data) : base64(together);
    if (e.format == "binary") return head + ">\n  " + encoded + "\n</DataArray>\n";
    head += " offset=\"" + std::to_string(appended.size()) + "\"/>\n";
    appended += e.appended_base64 ? encoded : std::string(together.begin(), together.end());
    return head;
  }

  std::string file(const std::string& type, const std::string& body) const {
    std::string xml = "<?xml version=\"1.0\"?>\n<VTKFile type=\"" + type + "\" version=\"1.0\" byte_order=\"" +
                      (e.big_endian ? "BigEndian" : "LittleEndian") + "\" header_type=\"" +
                      (e.header64 ? "UInt64" : "UInt32") + "\"" +
                      (e.compressed ? " compressor=\"vtkZLibDataCompressor\"" : "") + ">\n" + body;
    if (e.format == "appended")
      xml += "<AppendedData encoding=\"" + std::string(e.appended_base64 ? "base64" : "raw") + "\">\n_" + appended +
             "\n</AppendedData>\n";
    return xml + "</VTKFile>\n";
  }
};

}  // namespace sciray_test
