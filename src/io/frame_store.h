// A film's simulated frames on disk, one byte record per frame (docs/farm.md): the record file
// FOLDER/frames.bin (an 8-byte file header, then per frame a 32-byte record header and the frame's
// bytes compressed with zstd) and its index FOLDER/frames.idx (an 8-byte header, then 16 bytes per
// frame: the record's offset and length), so any frame is read with one seek. Each record names its
// frame and carries the sizes and a checksum of what it stores; a frame that does not check out is
// reported, never used. Frames are appended in order, record first, then its index entry, so a run
// killed at any point leaves a prefix of whole frames that `resume` finds and continues.
#pragma once

#include <cstddef>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "core/error.h"

namespace reel::io {

using Bytes = std::vector<std::byte>;

class FrameStoreWriter {
 public:
  FrameStoreWriter() = default;
  ~FrameStoreWriter();
  FrameStoreWriter(const FrameStoreWriter&) = delete;
  FrameStoreWriter& operator=(const FrameStoreWriter&) = delete;

  // Starts empty record and index files in FOLDER (which exists), replacing any there.
  Status create(const std::string& folder);
  // Opens FOLDER's files for appending after their last frame that reads back whole and checks
  // out (every record is verified, in the record file itself); anything after it (a torn record, a
  // bad checksum and all that follows) is cut off and the index is rewritten. A missing record
  // file: an empty store. Another writer holding the folder: an exit-2 kind of error. Returns the
  // number of good frames kept.
  Result<int> resume(const std::string& folder);
  // Appends frame `frames()` (they come in order); errors are the exit-4 kind.
  Status append(const Bytes& raw);
  int frames() const { return frames_; }
  // Flushes and syncs both files to disk.
  Status finish();
  // Closes both files, giving up the folder's lock.
  void close();

 private:
  Status fail(const std::string& what);
  Status busy() const;
  std::string folder_;
  std::FILE* data_ = nullptr;
  std::FILE* index_ = nullptr;
  std::uint64_t end_ = 0;  // the record file's length
  int frames_ = 0;
  void* cctx_ = nullptr;  // ZSTD_CCtx
};

class FrameStoreReader {
 public:
  FrameStoreReader() = default;
  ~FrameStoreReader();
  FrameStoreReader(FrameStoreReader&& o) noexcept;
  FrameStoreReader& operator=(FrameStoreReader&&) = delete;
  FrameStoreReader(const FrameStoreReader&) = delete;

  // Opens FOLDER's store (exit-2 kind of error when its files are missing or not a frame store).
  static Result<FrameStoreReader> open(const std::string& folder);
  // Frames the index lists (whole ones, though each is checked only when read).
  int frames() const { return static_cast<int>(index_.size()); }
  // Frame k's bytes; a torn or corrupted record is an exit-2 kind of error naming the frame.
  Result<Bytes> read(int k) const;

 private:
  std::string folder_;
  std::FILE* data_ = nullptr;
  std::vector<std::pair<std::uint64_t, std::uint64_t>> index_;  // offset, length
};

// The compression used by the store (zstd at a fast level, after the bytes are shuffled into
// planes of every 8th byte, which lets the similar high bytes of doubles compress together).
Bytes packFrame(const Bytes& raw, void* cctx = nullptr);
Result<Bytes> unpackFrame(const std::byte* packed, std::size_t n, std::size_t raw_size);

}  // namespace reel::io
