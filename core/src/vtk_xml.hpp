// SPDX-License-Identifier: MIT
// What the text and VTK outputs share (export.cpp, fields.cpp): XML and CSV quoting, the shortest
// text of a number, whole writes, and one VTK XML file with its arrays in an appended block.
#pragma once
#include <cerrno>
#include <charconv>
#include <cstdint>
#include <functional>
#include <string>
#include <utility>
#include <vector>

#include "binary_io.hpp"
#include "tumble/error.hpp"
#include "tumble/output_file.hpp"

namespace tumble::detail {

inline std::string xmlEscaped(const std::string& s) {
  std::string out;
  for (const char c : s) {
    switch (c) {
      case '&': out += "&amp;"; break;
      case '<': out += "&lt;"; break;
      case '>': out += "&gt;"; break;
      case '"': out += "&quot;"; break;
      case '\'': out += "&apos;"; break;
      default: out += c;
    }
  }
  return out;
}

// A CSV field, quoted when it holds a comma, a quote or a line break (RFC 4180).
inline std::string csvField(const std::string& v) {
  if (v.find_first_of(",\"\r\n") == std::string::npos) return v;
  std::string out = "\"";
  for (const char c : v) out += c == '"' ? std::string("\"\"") : std::string(1, c);
  return out + "\"";
}

// The shortest text that reads back to the same value (std::to_chars): a float as a float.
template <class T>
std::string number(T v) {
  char buf[64];
  const auto r = std::to_chars(buf, buf + sizeof buf, v);
  return std::string(buf, r.ptr);
}

inline void writeAll(OutputFile& out, const void* data, std::size_t size) {
  if (!writeFully(out.file(), data, size))
    throw Error(out.path() + ": cannot write: " + detail::errnoText(errno));
}

inline void writeAll(OutputFile& out, const std::string& s) { writeAll(out, s.data(), s.size()); }

// A CSV file written in chunks of about a megabyte: its header, then rows of fields (numbers in
// their shortest exact text, number()).
class CsvFile {
 public:
  CsvFile(const std::string& path, const std::string& header) : m_out(path), m_s(header + "\n") {}
  template <class T>
  void number(T v) {
    text(detail::number(v));
  }
  void text(const std::string& t) {
    if (!m_rowStart) m_s += ',';
    m_s += t;
    m_rowStart = false;
  }
  void endRow() {
    m_s += '\n';
    m_rowStart = true;
    if (m_s.size() > (1u << 20)) {
      writeAll(m_out, m_s);
      m_s.clear();
    }
  }
  void commit() {
    writeAll(m_out, m_s);
    m_out.commit();
  }

 private:
  OutputFile m_out;
  std::string m_s;
  bool m_rowStart = true;
};

// One VTK XML file of a data set type (PolyData, ImageData): the XML head lists each array with
// its offset into the appended block, which holds for each array a UInt64 byte count and then the
// values (header_type="UInt64"). `attributes`: the data set element's (ImageData's extent,
// origin and spacing).
class VtkXmlFile {
 public:
  explicit VtkXmlFile(std::string type, std::string attributes = "")
      : m_type(std::move(type)), m_attributes(std::move(attributes)) {}
  void array(const char* type, const std::string& name, int components,
             const std::function<void(detail::Encoder&)>& values) {
    m_xml += "        <DataArray type=\"" + std::string(type) + "\" Name=\"" + xmlEscaped(name) + "\"";
    if (components > 1) m_xml += " NumberOfComponents=\"" + std::to_string(components) + "\"";
    m_xml += " format=\"appended\" offset=\"" + std::to_string(m_data.size()) + "\"/>\n";
    const std::size_t at = m_data.size();
    detail::Encoder enc(m_data);
    enc.u64(0);
    values(enc);
    const std::uint64_t bytes = m_data.size() - at - 8;
    for (int k = 0; k < 8; ++k) m_data[at + k] = static_cast<std::uint8_t>(bytes >> (8 * k));
  }
  void xml(const std::string& s) { m_xml += s; }
  void write(const std::string& path) {
    OutputFile out(path);
    writeAll(out,
             "<?xml version=\"1.0\"?>\n"
             "<VTKFile type=\"" + m_type + "\" version=\"1.0\" byte_order=\"LittleEndian\" header_type=\"UInt64\">\n"
             "  <" + m_type + (m_attributes.empty() ? "" : " " + m_attributes) + ">\n" +
                 m_xml + "  </" + m_type + ">\n  <AppendedData encoding=\"raw\">\n   _");
    writeAll(out, m_data.data(), m_data.size());
    writeAll(out, "\n  </AppendedData>\n</VTKFile>\n");
    out.commit();
  }

 private:
  std::string m_type, m_attributes;
  std::string m_xml;
  std::vector<std::uint8_t> m_data;
};

}  // namespace tumble::detail
