// Render checkpoints: the film of the passes completed so far, bit for bit, with the settings
// that made it, so that an interrupted render continues to exactly the image it would have
// given without stopping (see renderer.h: passes are deterministic, film sums exact).
//
// File layout (little-endian throughout):
//   "BRUMECKP"                 8-byte magic
//   u32 version                kCheckpointVersion
//   str scenePath              informational (named in messages)
//   u32 n, n × (str, str)      settings as (name, value), compared on resume
//   i32 width, i32 height      film size
//   i32 passes                 completed passes
//   u64 nonFinite              samples and splats dropped so far
//   u8 hasSplats
//   u8 tracksNoise             1: the film tracks noise for adaptive stopping (film.h)
//   u64 stateBytes             the integrator's state (Integrator::saveState), may be 0
//   i128 × 3·w·h               the film's exact sums (film.h), row-major, top row first, each
//                              as u64 low half then u64 high half of the two's complement
//   with tracksNoise: i32 × w·h the passes each pixel took part in, then i128 × 3·w·h the
//                              sums of the squares of its values per pass
//   stateBytes bytes           the integrator's state
//   u64 checksum               FNV-1a 64 of every byte before it
// where str is u32 length + bytes (at most 4096). Version 4 added tracksNoise; version 3
// (without it, read as 0) is still read. Version 3: exact sums (version 2 kept doubles,
// sample and splat sums apart).
#pragma once
#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "brume/film/film.h"

namespace brume {

constexpr uint32_t kCheckpointVersion = 4;

// (name, value): what must match for a checkpoint to be continued, e.g. ("--spp", "64").
using CheckpointSettings = std::vector<std::pair<std::string, std::string>>;

struct Checkpoint {
    std::string scenePath;
    CheckpointSettings settings;
    uint64_t nonFinite = 0;
    Film film;
    std::string integratorState;
};

// Writes to "<path>.tmp-<pid>", flushes it to disk and renames it over `path`, so `path`
// always holds a whole checkpoint (the old one until the new one is complete). Throws
// std::runtime_error ("<path>: <problem>") on failure, leaving no temporary file.
void writeCheckpoint(const std::string& path, const std::string& scenePath, const CheckpointSettings& settings,
                     const Film& film, uint64_t nonFinite, const std::string& integratorState = {});

// Reads a checkpoint. A missing, truncated, corrupt or foreign file, or another version, is a
// std::runtime_error ("<path>: <problem>"); the file size is checked against its header
// before the film is allocated.
Checkpoint readCheckpoint(const std::string& path);

// Empty if `now` may continue a checkpoint made with `saved`, else one phrase naming the
// first difference, e.g. "--spp is 16 here but 8 in the checkpoint".
std::string checkpointMismatch(const CheckpointSettings& saved, const CheckpointSettings& now);

// Throws std::runtime_error unless a checkpoint can be written at `path` (by creating and
// removing its temporary file; `path` must not be a directory).
void checkCheckpointWritable(const std::string& path);

}  // namespace brume
