#include "brume/cli/value_parsers.h"

#include <cctype>
#include <cerrno>
#include <cmath>
#include <cstdlib>

namespace brume::cli {

int64_t parseInteger(const std::string& what, const std::string& text, int64_t lo, int64_t hi) {
    const char* s = text.c_str();
    char* end = nullptr;
    errno = 0;
    long long v = std::strtoll(s, &end, 10);
    bool digitsOnly = !text.empty() && (std::isdigit(static_cast<unsigned char>(text[0])) || text[0] == '-');
    if (!digitsOnly || end == s || *end != '\0' || errno == ERANGE)
        throw UsageError(what + ": '" + text + "' is not a whole number");
    if (v < lo || v > hi)
        throw UsageError(what + ": " + text + " is out of range [" + std::to_string(lo) + ", " +
                         std::to_string(hi) + "]");
    return v;
}

uint64_t parseUnsigned64(const std::string& what, const std::string& text) {
    const char* s = text.c_str();
    char* end = nullptr;
    errno = 0;
    unsigned long long v = std::strtoull(s, &end, 10);
    if (text.empty() || !std::isdigit(static_cast<unsigned char>(text[0])) || *end != '\0' || errno == ERANGE)
        throw UsageError(what + ": '" + text + "' is not a whole number in [0, 2^64)");
    return v;
}

double parsePositiveNumber(const std::string& what, const std::string& text, double hi) {
    const char* s = text.c_str();
    char* end = nullptr;
    errno = 0;
    double v = std::strtod(s, &end);
    if (text.empty() || end == s || *end != '\0' || errno == ERANGE || !std::isfinite(v))
        throw UsageError(what + ": '" + text + "' is not a number");
    if (!(v > 0) || v > hi) throw UsageError(what + ": " + text + " must be greater than 0 and at most " +
                                             std::to_string(int64_t(hi)));
    return v;
}

double parsePositiveSeconds(const std::string& what, const std::string& text, double hi) {
    return parsePositiveNumber(what, text, hi);
}

namespace {

// Why images are capped: refused before the film is allocated.
const char* const kSizeReason = " (the film keeps 24 to 48 bytes a pixel, 3 to 6 GiB at 2^27 pixels)";

std::string tooLarge(const std::string& what, const std::string& text) {
    return what + ": " + text + ": sides must be at most " + std::to_string(kMaxImageSide) + kSizeReason;
}

}  // namespace

void checkResolution(const std::string& what, Resolution r) {
    std::string text = std::to_string(r.width) + "x" + std::to_string(r.height);
    if (r.width < 1 || r.height < 1) throw UsageError(what + ": " + text + ": sides must be at least 1");
    if (r.width > kMaxImageSide || r.height > kMaxImageSide) throw UsageError(tooLarge(what, text));
    if (int64_t(r.width) * r.height > kMaxImagePixels)
        throw UsageError(what + ": " + text + ": more than 2^27 pixels" + kSizeReason);
}

Resolution parseResolution(const std::string& what, const std::string& text) {
    size_t x = text.find_first_of("xX");
    if (x == std::string::npos) throw UsageError(what + ": '" + text + "' is not of the form WIDTHxHEIGHT");
    auto side = [&](const std::string& part) {
        bool digits = !part.empty() && part.size() <= 9;
        for (char c : part) digits = digits && std::isdigit(static_cast<unsigned char>(c));
        if (!digits) {
            // Long digit strings are absurd sizes, not malformed ones.
            bool allDigits = !part.empty();
            for (char c : part) allDigits = allDigits && std::isdigit(static_cast<unsigned char>(c));
            if (allDigits) throw UsageError(tooLarge(what, text));
            throw UsageError(what + ": '" + text + "' is not of the form WIDTHxHEIGHT");
        }
        return int(std::strtol(part.c_str(), nullptr, 10));
    };
    Resolution r{side(text.substr(0, x)), side(text.substr(x + 1))};
    checkResolution(what, r);
    return r;
}

SamplerKind parseSamplerKind(const std::string& what, const std::string& text) {
    if (text == "sobol") return SamplerKind::Sobol;
    if (text == "independent") return SamplerKind::Independent;
    throw UsageError(what + ": unknown sampler '" + text + "' (sobol or independent)");
}

const char* samplerName(SamplerKind kind) { return kind == SamplerKind::Sobol ? "sobol" : "independent"; }

EmitterSampling parseEmitterSampling(const std::string& what, const std::string& text) {
    if (text == "solid-angle") return EmitterSampling::SolidAngle;
    if (text == "area") return EmitterSampling::Area;
    throw UsageError(what + ": unknown emitter sampling '" + text + "' (solid-angle or area)");
}

const char* emitterSamplingName(EmitterSampling e) { return e == EmitterSampling::Area ? "area" : "solid-angle"; }

}  // namespace brume::cli
