// Structural check of a ROS 1 bag before rosbag_storage reads it (ros_bag_structure.hpp).
#include "ros_bag_structure.hpp"

#include <bzlib.h>
#include <roslz4/lz4s.h>

#include <cstring>
#include <fstream>
#include <limits>
#include <map>
#include <set>
#include <string>
#include <vector>

#include "navaid/core/errors.hpp"

namespace navaid::io::detail {
namespace {

namespace fs = std::filesystem;
using Bytes = std::vector<char>;

constexpr std::uint8_t kMessageData = 0x02, kBagHeader = 0x03, kIndexData = 0x04, kChunk = 0x05, kChunkInfo = 0x06,
                       kConnection = 0x07;
// A chunk larger than this once decompressed is refused (rosbag_storage would allocate it).
constexpr std::uint64_t kMaxChunkBytes = 1ULL << 30;

class Checker {
 public:
  explicit Checker(const fs::path& path) : path_(path.string()) {}

  [[noreturn]] void fail(std::uint64_t offset, const std::string& what) const {
    throw IoError(path_, "not a well-formed ROS bag at byte " + std::to_string(offset) + ": " + what);
  }

  // "name=value" fields of a record header (or a connection record's data).
  std::map<std::string, std::string> fields(const char* p, std::uint64_t size, std::uint64_t offset) const {
    std::map<std::string, std::string> out;
    std::uint64_t at = 0;
    while (at < size) {
      if (size - at < 4) fail(offset + at, "a header field's length is cut off");
      std::uint32_t len = 0;
      std::memcpy(&len, p + at, 4);
      at += 4;
      if (len > size - at) fail(offset + at, "a header field of " + std::to_string(len) + " bytes overruns its header");
      const std::string field(p + at, len);
      const auto eq = field.find('=');
      if (eq == std::string::npos || eq == 0) fail(offset + at, "a header field is not name=value");
      out[field.substr(0, eq)] = field.substr(eq + 1);
      at += len;
    }
    return out;
  }

  // A fixed-size binary field that must be present with exactly `bytes` bytes.
  std::uint64_t number(const std::map<std::string, std::string>& f, const char* name, std::size_t bytes,
                       std::uint64_t offset) const {
    const auto it = f.find(name);
    if (it == f.end()) fail(offset, std::string("the record has no '") + name + "' field");
    if (it->second.size() != bytes)
      fail(offset, std::string("field '") + name + "' has " + std::to_string(it->second.size()) + " bytes, not " +
                       std::to_string(bytes));
    std::uint64_t v = 0;
    std::memcpy(&v, it->second.data(), bytes);
    return v;
  }

  struct Record {
    std::uint64_t offset = 0;
    std::uint8_t op = 0;
    std::map<std::string, std::string> header;
    std::uint64_t data_offset = 0, data_size = 0;
  };

  // The records of a buffer (a decompressed chunk), each checked for its op's fields.
  std::vector<Record> records(const char* p, std::uint64_t size, std::uint64_t base) const {
    std::vector<Record> out;
    std::uint64_t at = 0;
    while (at < size) {
      Record r;
      r.offset = at;
      if (size - at < 4) fail(base + at, "a record's header length is cut off");
      std::uint32_t header_len = 0;
      std::memcpy(&header_len, p + at, 4);
      at += 4;
      if (header_len > size - at) fail(base + at, "a record header of " + std::to_string(header_len) + " bytes overruns the data");
      r.header = fields(p + at, header_len, base + at);
      at += header_len;
      if (size - at < 4) fail(base + at, "a record's data length is cut off");
      std::uint32_t data_len = 0;
      std::memcpy(&data_len, p + at, 4);
      at += 4;
      if (data_len > size - at) fail(base + at, "record data of " + std::to_string(data_len) + " bytes overruns the data");
      r.data_offset = at;
      r.data_size = data_len;
      at += data_len;
      r.op = static_cast<std::uint8_t>(number(r.header, "op", 1, base + r.offset));
      out.push_back(std::move(r));
    }
    return out;
  }

  void check_connection(const Record& r, const char* data, std::uint64_t base) const {
    number(r.header, "conn", 4, base + r.offset);
    if (!r.header.count("topic")) fail(base + r.offset, "a connection record has no topic");
    const auto c = fields(data, r.data_size, base + r.data_offset);
    for (const char* key : {"type", "md5sum"})
      if (!c.count(key)) fail(base + r.data_offset, std::string("a connection has no '") + key + "'");
  }

  Bytes decompress(const Record& r, const char* data, std::uint64_t base) const {
    const auto compression = r.header.count("compression") ? r.header.at("compression") : std::string();
    const std::uint64_t size = number(r.header, "size", 4, base + r.offset);
    if (size > kMaxChunkBytes) fail(base + r.offset, "a chunk claims " + std::to_string(size) + " bytes decompressed");
    Bytes out(size);
    if (compression == "none") {
      if (r.data_size != size) fail(base + r.offset, "an uncompressed chunk's size does not match its data");
      std::memcpy(out.data(), data, size);
      return out;
    }
    unsigned int produced = static_cast<unsigned int>(size);
    int status = 0;
    Bytes in(data, data + r.data_size);  // the decompressors take non-const input
    if (compression == "bz2") {
      status = BZ2_bzBuffToBuffDecompress(out.data(), &produced, in.data(), static_cast<unsigned int>(in.size()), 0, 0);
      if (status != BZ_OK) fail(base + r.data_offset, "a bz2 chunk does not decompress (" + std::to_string(status) + ")");
    } else if (compression == "lz4") {
      status = roslz4_buffToBuffDecompress(in.data(), static_cast<unsigned int>(in.size()), out.data(), &produced);
      if (status != ROSLZ4_OK) fail(base + r.data_offset, "an lz4 chunk does not decompress (" + std::to_string(status) + ")");
    } else {
      fail(base + r.offset, "unknown chunk compression '" + compression + "'");
    }
    if (produced != size) fail(base + r.offset, "a chunk decompresses to another size than it declares");
    return out;
  }

 private:
  std::string path_;
};

}  // namespace

void check_ros_bag_structure(const fs::path& path) {
  const Checker c(path);
  std::ifstream in(path, std::ios::binary);
  if (!in) throw IoError(path.string(), "cannot be opened");
  in.seekg(0, std::ios::end);
  const std::uint64_t file_size = static_cast<std::uint64_t>(in.tellg());
  const auto read = [&](std::uint64_t offset, std::uint64_t n) {
    Bytes b(n);
    in.seekg(static_cast<std::streamoff>(offset));
    in.read(b.data(), static_cast<std::streamsize>(n));
    if (static_cast<std::uint64_t>(in.gcount()) != n) c.fail(offset, "the file ends early");
    return b;
  };
  constexpr std::uint64_t kMagic = 13;
  if (file_size < kMagic || std::string(read(0, kMagic).data(), kMagic) != "#ROSBAG V2.0\n")
    throw IoError(path.string(), "is not a ROS 1 bag (no '#ROSBAG V2.0' header)");

  // The top-level records, their headers read and their data left on disk.
  std::vector<Checker::Record> top;
  std::map<std::uint64_t, std::size_t> at_offset;
  for (std::uint64_t pos = kMagic; pos < file_size;) {
    Checker::Record r;
    r.offset = pos;
    if (file_size - pos < 4) c.fail(pos, "a record's header length is cut off");
    std::uint32_t header_len = 0;
    std::memcpy(&header_len, read(pos, 4).data(), 4);
    if (header_len > file_size - pos - 4) c.fail(pos, "a record header of " + std::to_string(header_len) + " bytes overruns the file");
    r.header = c.fields(read(pos + 4, header_len).data(), header_len, pos + 4);
    const std::uint64_t after = pos + 4 + header_len;
    if (file_size - after < 4) c.fail(after, "a record's data length is cut off");
    std::uint32_t data_len = 0;
    std::memcpy(&data_len, read(after, 4).data(), 4);
    r.data_offset = after + 4;
    if (data_len > file_size - r.data_offset) c.fail(after, "record data of " + std::to_string(data_len) + " bytes overruns the file");
    r.data_size = data_len;
    r.op = static_cast<std::uint8_t>(c.number(r.header, "op", 1, pos));
    at_offset[pos] = top.size();
    top.push_back(std::move(r));
    pos = top.back().data_offset + data_len;
  }
  if (top.empty() || top.front().op != kBagHeader) c.fail(kMagic, "the first record is not the bag header");
  const std::uint64_t index_pos = c.number(top.front().header, "index_pos", 8, kMagic);
  c.number(top.front().header, "conn_count", 4, kMagic);
  c.number(top.front().header, "chunk_count", 4, kMagic);
  if (index_pos != 0 && !at_offset.count(index_pos)) c.fail(kMagic, "the index position is not the start of a record");

  std::set<std::uint64_t> inner_starts;  // message records of the chunk the index records follow
  for (std::size_t i = 1; i < top.size(); ++i) {
    const auto& r = top[i];
    switch (r.op) {
      case kChunk: {
        const Bytes inner = c.decompress(r, read(r.data_offset, r.data_size).data(), 0);
        inner_starts.clear();
        for (const auto& m : c.records(inner.data(), inner.size(), r.data_offset)) {
          if (m.op == kConnection) {
            c.check_connection(m, inner.data() + m.data_offset, r.data_offset);
          } else if (m.op == kMessageData) {
            c.number(m.header, "conn", 4, r.data_offset + m.offset);
            c.number(m.header, "time", 8, r.data_offset + m.offset);
            inner_starts.insert(m.offset);
          } else {
            c.fail(r.data_offset + m.offset, "a chunk holds a record of op " + std::to_string(m.op));
          }
        }
        break;
      }
      case kIndexData: {
        if (c.number(r.header, "ver", 4, r.offset) != 1) c.fail(r.offset, "unknown index version");
        c.number(r.header, "conn", 4, r.offset);
        const std::uint64_t count = c.number(r.header, "count", 4, r.offset);
        if (r.data_size != count * 12) c.fail(r.offset, "an index record's data does not hold its count of entries");
        const Bytes entries = read(r.data_offset, r.data_size);
        for (std::uint64_t k = 0; k < count; ++k) {
          std::uint32_t entry = 0;
          std::memcpy(&entry, entries.data() + k * 12 + 8, 4);
          if (!inner_starts.count(entry)) c.fail(r.offset, "an index entry points into the middle of its chunk");
        }
        break;
      }
      case kConnection:
        c.check_connection(r, read(r.data_offset, r.data_size).data(), 0);
        break;
      case kChunkInfo: {
        if (c.number(r.header, "ver", 4, r.offset) != 1) c.fail(r.offset, "unknown chunk info version");
        const std::uint64_t chunk_pos = c.number(r.header, "chunk_pos", 8, r.offset);
        c.number(r.header, "start_time", 8, r.offset);
        c.number(r.header, "end_time", 8, r.offset);
        const std::uint64_t count = c.number(r.header, "count", 4, r.offset);
        if (r.data_size != count * 8) c.fail(r.offset, "a chunk info record's data does not hold its count of entries");
        const auto chunk = at_offset.find(chunk_pos);
        if (chunk == at_offset.end() || top[chunk->second].op != kChunk) c.fail(r.offset, "a chunk info record points at no chunk");
        break;
      }
      default:
        c.fail(r.offset, "a record of unknown op " + std::to_string(r.op));
    }
  }
}

}  // namespace navaid::io::detail
