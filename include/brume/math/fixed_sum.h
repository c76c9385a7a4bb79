// Exact sums of floats: every value converted to a 128-bit fixed-point integer in units of
// 2^-64 (float values are multiples of 2^-149, so every float of magnitude 2^-40 or more
// converts exactly; smaller ones are truncated towards zero, a change below 2^-64 absolute;
// magnitudes above 2^62 are clamped). Integer addition is associative, so a sum does not
// depend on the order of its terms, and a part of it can be taken out again exactly. The
// film keeps its pixels so (film.h); so does the efficiency-aware tracer for the passes it
// leaves out of the image (allocation_planner.h).
#pragma once

namespace brume {

__extension__ typedef __int128 FixedSum;

FixedSum toFixed(float v);  // 0 for non-finite values
inline double fromFixed(FixedSum s) { return double(s) * 0x1p-64; }

}  // namespace brume
