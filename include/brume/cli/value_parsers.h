// Checked parsers for option values: whole numbers in a range, seconds, image sizes. Every
// problem is a UsageError with a one-line message that starts with `what` (the option).
#pragma once
#include <cstdint>
#include <string>

#include "brume/cli/usage_error.h"
#include "brume/sampling/sampler.h"
#include "brume/scene/scene.h"

namespace brume::cli {

struct Resolution {
    int width = 0, height = 0;
};

constexpr int kMaxImageSide = 16384;
constexpr int64_t kMaxImagePixels = int64_t(1) << 27;

// Whole decimal numbers in [lo, hi].
int64_t parseInteger(const std::string& what, const std::string& text, int64_t lo, int64_t hi);
uint64_t parseUnsigned64(const std::string& what, const std::string& text);
// A finite decimal number in (0, hi]: any quantity, or seconds.
double parsePositiveNumber(const std::string& what, const std::string& text, double hi);
double parsePositiveSeconds(const std::string& what, const std::string& text, double hi);
// "WxH", each side in [1, kMaxImageSide], at most kMaxImagePixels pixels.
Resolution parseResolution(const std::string& what, const std::string& text);
// Throws UsageError unless the resolution is within the limits above.
void checkResolution(const std::string& what, Resolution r);
// "sobol" or "independent", and back.
SamplerKind parseSamplerKind(const std::string& what, const std::string& text);
const char* samplerName(SamplerKind kind);
// "solid-angle" or "area", and back.
EmitterSampling parseEmitterSampling(const std::string& what, const std::string& text);
const char* emitterSamplingName(EmitterSampling e);

}  // namespace brume::cli
