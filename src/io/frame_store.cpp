#include "io/frame_store.h"

#include <sys/file.h>
#include <sys/stat.h>
#include <unistd.h>
#include <zstd.h>

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <filesystem>

#include "core/hash.h"

namespace reel::io {
namespace {

namespace fs = std::filesystem;
constexpr char kDataMagic[9] = "REELFRM1";
constexpr char kIndexMagic[9] = "REELIDX1";
constexpr std::uint32_t kRecordMagic = 0x31524652;  // "RFR1"
constexpr int kLevel = 3;
constexpr std::size_t kPlanes = 8;
constexpr std::uint64_t kMaxRecord = std::uint64_t{1} << 34;  // 16 GiB: beyond it, a record is garbage

struct RecordHeader {
  std::uint32_t magic = kRecordMagic;
  std::uint32_t frame = 0;
  std::uint64_t raw_size = 0;
  std::uint64_t stored_size = 0;
  std::uint64_t checksum = 0;  // FNV-1a of the stored bytes
};
static_assert(sizeof(RecordHeader) == 32);

struct IndexEntry {
  std::uint64_t offset = 0, length = 0;
};
static_assert(sizeof(IndexEntry) == 16);

std::uint64_t checksum(const std::byte* p, std::size_t n) { return hashBytes(p, n).h; }

std::string dataPath(const std::string& folder) { return (fs::path(folder) / "frames.bin").string(); }
std::string indexPath(const std::string& folder) { return (fs::path(folder) / "frames.idx").string(); }

// One writer at a time: an exclusive lock on the record file, held while it is open (a second
// `reel simulate --cache` of the same folder, say a requeued job whose first run still goes, is
// refused instead of interleaving frames).
bool lockWriter(std::FILE* f) { return ::flock(fileno(f), LOCK_EX | LOCK_NB) == 0; }

bool readAt(std::FILE* f, std::uint64_t offset, void* out, std::size_t n) {
  return fseeko(f, static_cast<off_t>(offset), SEEK_SET) == 0 && std::fread(out, 1, n, f) == n;
}

// The whole index file's entries (empty when it is missing or not an index).
std::vector<IndexEntry> readIndex(const std::string& path, bool& valid) {
  std::vector<IndexEntry> out;
  valid = false;
  std::FILE* f = std::fopen(path.c_str(), "rb");
  if (!f) return out;
  char magic[8];
  if (std::fread(magic, 1, 8, f) == 8 && std::memcmp(magic, kIndexMagic, 8) == 0) {
    valid = true;
    IndexEntry e;
    while (std::fread(&e, sizeof e, 1, f) == 1) out.push_back(e);
  }
  std::fclose(f);
  return out;
}

// Frame k's record at `e`, checked: the header names the frame, the sizes fit the entry, the
// stored bytes match their checksum and unpack to the raw size.
Result<Bytes> readRecord(std::FILE* f, const std::string& file, int k, const IndexEntry& e) {
  const std::string where = file + ": frame " + std::to_string(k);
  RecordHeader h;
  if (e.length < sizeof h || e.length > kMaxRecord || !readAt(f, e.offset, &h, sizeof h))
    return Error(ErrorKind::BadInput, where + " is cut short (the cache is truncated; `reel simulate --resume` rewrites it)");
  if (h.magic != kRecordMagic || h.frame != static_cast<std::uint32_t>(k) || h.stored_size != e.length - sizeof h ||
      h.raw_size > kMaxRecord)
    return Error(ErrorKind::BadInput, where + ": its record header is damaged (`reel simulate --resume` rewrites it)");
  // Nothing is allocated for bytes the file does not hold, nor for a raw size the checksummed
  // data does not name: the header's sizes are not under the checksum, and a changed one must be
  // refused before it is believed (a forged raw size of 8 GiB once ran reel out of memory).
  struct stat st {};
  if (::fstat(fileno(f), &st) != 0 || e.offset + e.length > static_cast<std::uint64_t>(st.st_size))
    return Error(ErrorKind::BadInput, where + " is cut short (the cache is truncated; `reel simulate --resume` rewrites it)");
  Bytes stored(h.stored_size);
  if (std::fread(stored.data(), 1, stored.size(), f) != stored.size())
    return Error(ErrorKind::BadInput, where + " is cut short (the cache is truncated; `reel simulate --resume` rewrites it)");
  if (checksum(stored.data(), stored.size()) != h.checksum)
    return Error(ErrorKind::BadInput, where + ": checksum mismatch, the frame is corrupted (`reel simulate --resume` rewrites it)");
  // The compressed frame records its own content size (under the checksum): the header's must agree.
  if (ZSTD_getFrameContentSize(stored.data(), stored.size()) != h.raw_size)
    return Error(ErrorKind::BadInput, where + ": its record header is damaged (`reel simulate --resume` rewrites it)");
  auto raw = unpackFrame(stored.data(), stored.size(), h.raw_size);
  if (!raw.ok()) return Error(ErrorKind::BadInput, where + ": " + raw.error().headline());
  return raw;
}

}  // namespace

Bytes packFrame(const Bytes& raw, void* cctx) {
  // Planes of every 8th byte: byte p of each 8-byte word together, then the tail as it is.
  const std::size_t n = raw.size(), words = n / kPlanes;
  Bytes shuffled(n);
  for (std::size_t p = 0; p < kPlanes; ++p)
    for (std::size_t i = 0; i < words; ++i) shuffled[p * words + i] = raw[i * kPlanes + p];
  std::copy(raw.begin() + static_cast<std::ptrdiff_t>(words * kPlanes), raw.end(),
            shuffled.begin() + static_cast<std::ptrdiff_t>(words * kPlanes));  // (an empty frame: nothing, no null pointer)
  Bytes out(ZSTD_compressBound(n));
  const std::size_t got = cctx ? ZSTD_compressCCtx(static_cast<ZSTD_CCtx*>(cctx), out.data(), out.size(),
                                                   shuffled.data(), n, kLevel)
                               : ZSTD_compress(out.data(), out.size(), shuffled.data(), n, kLevel);
  out.resize(ZSTD_isError(got) ? 0 : got);  // (cannot fail with a bound-sized buffer)
  return out;
}

Result<Bytes> unpackFrame(const std::byte* packed, std::size_t n, std::size_t raw_size) {
  Bytes shuffled(raw_size);
  const std::size_t got = ZSTD_decompress(shuffled.data(), raw_size, packed, n);
  if (ZSTD_isError(got) || got != raw_size)
    return Error(ErrorKind::BadInput, std::string("does not decompress: ") +
                                          (ZSTD_isError(got) ? ZSTD_getErrorName(got) : "wrong size"));
  const std::size_t words = raw_size / kPlanes;
  Bytes raw(raw_size);
  for (std::size_t p = 0; p < kPlanes; ++p)
    for (std::size_t i = 0; i < words; ++i) raw[i * kPlanes + p] = shuffled[p * words + i];
  std::copy(shuffled.begin() + static_cast<std::ptrdiff_t>(words * kPlanes), shuffled.end(),
            raw.begin() + static_cast<std::ptrdiff_t>(words * kPlanes));
  return raw;
}

FrameStoreWriter::~FrameStoreWriter() {
  close();
  ZSTD_freeCCtx(static_cast<ZSTD_CCtx*>(cctx_));
}

void FrameStoreWriter::close() {
  if (data_) std::fclose(data_);
  if (index_) std::fclose(index_);
  data_ = index_ = nullptr;
}

Status FrameStoreWriter::fail(const std::string& what) {
  const int e = errno;
  return Error(ErrorKind::Output, folder_ + ": " + what + ": " + std::strerror(e ? e : EIO));
}

Status FrameStoreWriter::busy() const {
  return Error(ErrorKind::BadInput, folder_ + ": another reel is writing this cache now (wait for it, or stop it)");
}

Status FrameStoreWriter::create(const std::string& folder) {
  folder_ = folder;
  if (!cctx_) cctx_ = ZSTD_createCCtx();
  // Opened without truncating, locked, then emptied: a running writer's file is never cut.
  data_ = std::fopen(dataPath(folder).c_str(), "ab");
  if (!data_) return fail("cannot write frames.bin");
  if (!lockWriter(data_)) return busy();
  if (::ftruncate(fileno(data_), 0) != 0) return fail("cannot write frames.bin");
  index_ = std::fopen(indexPath(folder).c_str(), "wb");
  if (!index_) return fail("cannot write frames.idx");
  if (std::fwrite(kDataMagic, 1, 8, data_) != 8 || std::fwrite(kIndexMagic, 1, 8, index_) != 8)
    return fail("cannot write");
  end_ = 8;
  frames_ = 0;
  return {};
}

Result<int> FrameStoreWriter::resume(const std::string& folder) {
  folder_ = folder;
  // Locked first, then read: what is checked is what no other writer changes meanwhile.
  data_ = std::fopen(dataPath(folder).c_str(), "ab");
  if (!data_) return fail("cannot append").error();
  if (!lockWriter(data_)) return busy().error();
  std::FILE* f = std::fopen(dataPath(folder).c_str(), "rb");
  char magic[8];
  if (!f || std::fread(magic, 1, 8, f) != 8 || std::memcmp(magic, kDataMagic, 8) != 0) {
    if (f) std::fclose(f);
    std::fclose(data_);  // (create locks its own)
    data_ = nullptr;
    if (Status st = create(folder); !st) return st.error();
    return 0;
  }
  // The good frames are found in the record file itself, record by record (each names its frame
  // and carries its sizes and checksum), so a lost or damaged index costs nothing: it is rewritten.
  std::vector<IndexEntry> good;
  std::uint64_t end = 8;
  for (;;) {
    RecordHeader h;
    if (!readAt(f, end, &h, sizeof h) || h.stored_size > kMaxRecord) break;
    const IndexEntry e{end, sizeof h + h.stored_size};
    if (!readRecord(f, "", static_cast<int>(good.size()), e).ok()) break;
    good.push_back(e);
    end += e.length;
  }
  std::fclose(f);
  if (::ftruncate(fileno(data_), static_cast<off_t>(end)) != 0)
    return fail("cannot cut frames.bin back to its last whole frame").error();
  index_ = std::fopen(indexPath(folder).c_str(), "wb");
  if (!index_ || std::fwrite(kIndexMagic, 1, 8, index_) != 8 ||
      (!good.empty() && std::fwrite(good.data(), sizeof(IndexEntry), good.size(), index_) != good.size()) ||
      std::fflush(index_) != 0)
    return fail("cannot rewrite frames.idx").error();
  if (!cctx_) cctx_ = ZSTD_createCCtx();
  end_ = end;
  frames_ = static_cast<int>(good.size());
  return frames_;
}

Status FrameStoreWriter::append(const Bytes& raw) {
  if (!data_ || !index_) return Error(ErrorKind::Output, folder_ + ": the frame store is not open");
  const Bytes stored = packFrame(raw, cctx_);
  RecordHeader h;
  h.frame = static_cast<std::uint32_t>(frames_);
  h.raw_size = raw.size();
  h.stored_size = stored.size();
  h.checksum = checksum(stored.data(), stored.size());
  // The record whole before its index entry: an entry always points at a complete record.
  if (std::fwrite(&h, sizeof h, 1, data_) != 1 || std::fwrite(stored.data(), 1, stored.size(), data_) != stored.size() ||
      std::fflush(data_) != 0)
    return fail("cannot write frame " + std::to_string(frames_));
  const IndexEntry e{end_, sizeof h + stored.size()};
  if (std::fwrite(&e, sizeof e, 1, index_) != 1 || std::fflush(index_) != 0)
    return fail("cannot write the index of frame " + std::to_string(frames_));
  end_ += e.length;
  ++frames_;
  return {};
}

Status FrameStoreWriter::finish() {
  for (std::FILE* f : {data_, index_})
    if (f && (std::fflush(f) != 0 || ::fsync(fileno(f)) != 0)) return fail("cannot sync");
  return {};
}

FrameStoreReader::~FrameStoreReader() {
  if (data_) std::fclose(data_);
}

FrameStoreReader::FrameStoreReader(FrameStoreReader&& o) noexcept
    : folder_(std::move(o.folder_)), data_(o.data_), index_(std::move(o.index_)) {
  o.data_ = nullptr;
}

Result<FrameStoreReader> FrameStoreReader::open(const std::string& folder) {
  FrameStoreReader r;
  r.folder_ = folder;
  bool valid = false;
  const std::vector<IndexEntry> index = readIndex(indexPath(folder), valid);
  if (!valid)
    return Error(ErrorKind::BadInput, indexPath(folder) + ": missing or not a reel frame index (`reel simulate --resume` rebuilds it)");
  r.data_ = std::fopen(dataPath(folder).c_str(), "rb");
  if (!r.data_) return Error(ErrorKind::BadInput, dataPath(folder) + ": cannot open: " + std::strerror(errno));
  char magic[8];
  if (std::fread(magic, 1, 8, r.data_) != 8 || std::memcmp(magic, kDataMagic, 8) != 0)
    return Error(ErrorKind::BadInput, dataPath(folder) + ": not a reel frame store");
  for (const IndexEntry& e : index) r.index_.push_back({e.offset, e.length});
  return r;
}

Result<Bytes> FrameStoreReader::read(int k) const {
  if (k < 0 || k >= frames())
    return Error(ErrorKind::BadInput, dataPath(folder_) + ": frame " + std::to_string(k) + " is not in the cache (it holds " +
                                          (frames() ? "frames 0.." + std::to_string(frames() - 1) : "no frames") + ")");
  const auto& [offset, length] = index_[static_cast<std::size_t>(k)];
  return readRecord(data_, dataPath(folder_), k, IndexEntry{offset, length});
}

}  // namespace reel::io
