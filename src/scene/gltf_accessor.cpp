// glTF loader: reading accessors, with every index and byte range checked before a read.
#include <cmath>
#include <cstring>

#include "brume/scene/gltf_detail.h"

namespace brume::gltf {

namespace {

const char* typeName(int type) {
    switch (type) {
    case TINYGLTF_TYPE_SCALAR: return "SCALAR";
    case TINYGLTF_TYPE_VEC2: return "VEC2";
    case TINYGLTF_TYPE_VEC3: return "VEC3";
    case TINYGLTF_TYPE_VEC4: return "VEC4";
    case TINYGLTF_TYPE_MAT2: return "MAT2";
    case TINYGLTF_TYPE_MAT3: return "MAT3";
    case TINYGLTF_TYPE_MAT4: return "MAT4";
    default: return "unknown type";
    }
}

const char* componentName(int componentType) {
    switch (componentType) {
    case TINYGLTF_COMPONENT_TYPE_BYTE: return "BYTE";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return "UNSIGNED_BYTE";
    case TINYGLTF_COMPONENT_TYPE_SHORT: return "SHORT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: return "UNSIGNED_SHORT";
    case TINYGLTF_COMPONENT_TYPE_INT: return "INT";
    case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: return "UNSIGNED_INT";
    case TINYGLTF_COMPONENT_TYPE_FLOAT: return "FLOAT";
    case TINYGLTF_COMPONENT_TYPE_DOUBLE: return "DOUBLE";
    default: return "unknown component type";
    }
}

// An accessor whose bytes have been checked to lie inside its buffer view and buffer.
struct View {
    const unsigned char* base = nullptr;  // nullptr: no buffer view, every value is 0
    size_t stride = 0, count = 0;
    int componentType = 0, components = 0, componentSize = 0;
    bool normalized = false;

    double component(size_t i, int c) const {
        if (!base) return 0;
        const unsigned char* p = base + i * stride + size_t(c) * size_t(componentSize);
        switch (componentType) {
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE: return *p;
        case TINYGLTF_COMPONENT_TYPE_BYTE: return double(int8_t(*p));
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT: { uint16_t v; std::memcpy(&v, p, 2); return v; }
        case TINYGLTF_COMPONENT_TYPE_SHORT: { int16_t v; std::memcpy(&v, p, 2); return v; }
        case TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT: { uint32_t v; std::memcpy(&v, p, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_INT: { int32_t v; std::memcpy(&v, p, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_FLOAT: { float v; std::memcpy(&v, p, 4); return v; }
        case TINYGLTF_COMPONENT_TYPE_DOUBLE: { double v; std::memcpy(&v, p, 8); return v; }
        default: return 0;
        }
    }
};

View view(const Source& src, const tinygltf::Model& model, int index, const std::string& usage, int type) {
    checkIndex(src, index, model.accessors.size(), usage, "accessor");
    const tinygltf::Accessor& a = model.accessors[size_t(index)];
    const std::string field = at("accessors", size_t(index)), as = " (used as " + usage + ")";
    if (a.sparse.isSparse) src.fail(field + ".sparse", "sparse accessors are not supported" + as);
    if (a.type != type)
        src.fail(field + ".type", std::string(typeName(a.type)) + " where " + typeName(type) + " is needed" + as);

    View v;
    v.components = tinygltf::GetNumComponentsInType(uint32_t(a.type));
    v.componentSize = tinygltf::GetComponentSizeInBytes(uint32_t(a.componentType));
    if (v.components <= 0 || v.componentSize <= 0)
        src.fail(field + ".componentType", "unknown component type " + std::to_string(a.componentType) + as);
    v.componentType = a.componentType;
    v.normalized = a.normalized;
    v.count = a.count;
    const size_t element = size_t(v.components) * size_t(v.componentSize);

    if (a.bufferView == -1) {  // glTF: an accessor without a buffer view holds zeros
        if (a.count > (size_t(1) << 26))
            src.fail(field + ".count", std::to_string(a.count) + " elements without a bufferView is too many" + as);
        return v;
    }
    size_t length = 0;
    const unsigned char* bytes = bufferViewBytes(src, model, a.bufferView, field + ".bufferView", &length);
    const tinygltf::BufferView& bv = model.bufferViews[size_t(a.bufferView)];
    v.stride = bv.byteStride ? bv.byteStride : element;
    if (v.stride < element)
        src.fail(at("bufferViews", size_t(a.bufferView)) + ".byteStride",
                 "stride " + std::to_string(v.stride) + " is smaller than the " + std::to_string(element) +
                     "-byte elements of " + field);
    if (a.count > 0) {
        // byteOffset + (count − 1)·stride + element ≤ length, without overflow.
        size_t rest = a.byteOffset <= length ? length - a.byteOffset : 0;
        if (a.byteOffset > length || element > rest || (a.count - 1) > (rest - element) / v.stride)
            src.fail(field, std::to_string(a.count) + " elements of " + std::to_string(element) + " bytes (stride " +
                                std::to_string(v.stride) + ") from byteOffset " + std::to_string(a.byteOffset) +
                                " do not fit in the " + std::to_string(length) + " bytes of bufferViews[" +
                                std::to_string(a.bufferView) + "]" + as);
    }
    v.base = bytes + a.byteOffset;
    return v;
}

}  // namespace

const unsigned char* bufferViewBytes(const Source& src, const tinygltf::Model& model, int index,
                                     const std::string& field, size_t* length) {
    checkIndex(src, index, model.bufferViews.size(), field, "bufferView");
    const tinygltf::BufferView& bv = model.bufferViews[size_t(index)];
    const std::string bvField = at("bufferViews", size_t(index));
    checkIndex(src, bv.buffer, model.buffers.size(), bvField + ".buffer", "buffer");
    const std::vector<unsigned char>& data = model.buffers[size_t(bv.buffer)].data;
    if (bv.byteOffset > data.size() || bv.byteLength > data.size() - bv.byteOffset)
        src.fail(bvField, "byteOffset " + std::to_string(bv.byteOffset) + " + byteLength " +
                              std::to_string(bv.byteLength) + " exceeds the " + std::to_string(data.size()) +
                              " bytes of buffers[" + std::to_string(bv.buffer) + "]");
    *length = bv.byteLength;
    return data.data() + bv.byteOffset;
}

std::vector<float> readFloats(const Source& src, const tinygltf::Model& model, int index, const std::string& usage,
                              int type, bool allowNormalized) {
    View v = view(src, model, index, usage, type);
    const std::string field = at("accessors", size_t(index)), as = " (used as " + usage + ")";
    double scale = 1;
    if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE && allowNormalized) {
        scale = 1.0 / 255.0;
    } else if (v.componentType == TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT && allowNormalized) {
        scale = 1.0 / 65535.0;
    } else if (v.componentType != TINYGLTF_COMPONENT_TYPE_FLOAT) {
        src.fail(field + ".componentType",
                 std::string(componentName(v.componentType)) + " where FLOAT" +
                     (allowNormalized ? " or normalized UNSIGNED_BYTE/UNSIGNED_SHORT" : "") + " is needed" + as);
    }
    if (scale != 1 && !v.normalized)
        src.fail(field + ".normalized", "integer components must be normalized here" + as);

    std::vector<float> out(v.count * size_t(v.components));
    for (size_t i = 0; i < v.count; ++i)
        for (int c = 0; c < v.components; ++c) {
            double x = v.component(i, c) * scale;
            if (!std::isfinite(x))
                src.fail(field, "element " + std::to_string(i) + " component " + std::to_string(c) + " is " + num(x) +
                                    as);
            out[i * size_t(v.components) + size_t(c)] = float(x);
        }
    return out;
}

std::vector<uint32_t> readIndices(const Source& src, const tinygltf::Model& model, int index,
                                  const std::string& usage) {
    View v = view(src, model, index, usage, TINYGLTF_TYPE_SCALAR);
    if (v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_BYTE &&
        v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_SHORT &&
        v.componentType != TINYGLTF_COMPONENT_TYPE_UNSIGNED_INT)
        src.fail(at("accessors", size_t(index)) + ".componentType",
                 std::string(componentName(v.componentType)) +
                     " where UNSIGNED_BYTE, UNSIGNED_SHORT or UNSIGNED_INT is needed (used as " + usage + ")");
    std::vector<uint32_t> out(v.count);
    for (size_t i = 0; i < v.count; ++i) out[i] = uint32_t(v.component(i, 0));
    return out;
}

}  // namespace brume::gltf
