#include "e57_xml_tree.hpp"

#include <libxml/parser.h>
#include <libxml/tree.h>

#include <bit>
#include <cstdlib>
#include <limits>
#include <memory>

#include "e57_format.hpp"

namespace handscan::exporter::e57 {
namespace {

const char* chars(const xmlChar* s) { return reinterpret_cast<const char*>(s); }

std::string qualifiedName(const xmlNode* n) {
    std::string name = chars(n->name);
    if (n->ns && n->ns->prefix) name = std::string(chars(n->ns->prefix)) + ":" + name;
    return name;
}

const xmlNode* child(const xmlNode* parent, const std::string& name) {
    if (!parent) return nullptr;
    for (const xmlNode* c = parent->children; c; c = c->next) {
        if (c->type == XML_ELEMENT_NODE && qualifiedName(c) == name) return c;
    }
    return nullptr;
}

std::string text(const xmlNode* n) {
    if (!n) return {};
    xmlChar* t = xmlNodeGetContent(n);  // CDATA included
    std::string s = t ? chars(t) : "";
    xmlFree(t);
    return s;
}

std::optional<std::string> attribute(const xmlNode* n, const char* name) {
    xmlChar* v = xmlGetProp(n, reinterpret_cast<const xmlChar*>(name));
    if (!v) return std::nullopt;
    std::string s = chars(v);
    xmlFree(v);
    return s;
}

double number(const xmlNode* n, double fallback) {
    const std::string s = text(n);
    return s.empty() ? fallback : std::strtod(s.c_str(), nullptr);
}

unsigned bitsFor(std::int64_t minimum, std::int64_t maximum) {
    const std::uint64_t range =
        static_cast<std::uint64_t>(maximum) - static_cast<std::uint64_t>(minimum);
    return range == 0 ? 0u : static_cast<unsigned>(std::bit_width(range));
}

Result<E57Field> field(const xmlNode* n, const std::string& where) {
    E57Field f;
    f.name = qualifiedName(n);
    const std::string type = attribute(n, "type").value_or("");
    auto integer = [&](const char* a, std::int64_t fallback) {
        const auto v = attribute(n, a);
        return v ? std::strtoll(v->c_str(), nullptr, 10) : fallback;
    };
    if (type == "Float") {
        f.single = attribute(n, "precision").value_or("double") == "single";
        f.bits = f.single ? 32 : 64;
        return f;
    }
    if (type != "Integer" && type != "ScaledInteger") {
        return Status(StatusCode::kUnsupported, where + ": prototype field " + f.name +
                                                    " has type '" + type +
                                                    "' (expected Float, Integer, ScaledInteger)");
    }
    f.kind = type == "Integer" ? E57Field::Kind::kInteger : E57Field::Kind::kScaledInteger;
    f.minimum = integer("minimum", std::numeric_limits<std::int64_t>::min());
    f.maximum = integer("maximum", std::numeric_limits<std::int64_t>::max());
    if (f.maximum < f.minimum)
        return Status(StatusCode::kProtocolError, where + ": " + f.name + " maximum < minimum");
    if (const auto s = attribute(n, "scale")) f.scale = std::strtod(s->c_str(), nullptr);
    if (const auto o = attribute(n, "offset")) f.offset = std::strtod(o->c_str(), nullptr);
    f.bits = bitsFor(f.minimum, f.maximum);
    return f;
}

Result<E57CompressedVector> compressedVector(const xmlNode* n, const std::string& where) {
    E57CompressedVector v;
    const auto offset = attribute(n, "fileOffset");
    const auto count = attribute(n, "recordCount");
    if (!offset || !count) {
        return Status(StatusCode::kProtocolError, where + ": CompressedVector " + qualifiedName(n) +
                                                      " without fileOffset or recordCount");
    }
    v.file_offset = std::strtoull(offset->c_str(), nullptr, 10);
    v.records = std::strtoull(count->c_str(), nullptr, 10);
    const xmlNode* proto = child(n, "prototype");
    if (!proto)
        return Status(StatusCode::kProtocolError,
                      where + ": " + qualifiedName(n) + " has no prototype");
    for (const xmlNode* c = proto->children; c; c = c->next) {
        if (c->type != XML_ELEMENT_NODE) continue;
        auto f = field(c, where);
        if (!f.isOk()) return f.status();
        v.fields.push_back(*f);
    }
    return v;
}

Result<E57Scan> scan(const xmlNode* n, const std::string& where) {
    E57Scan s;
    s.guid = text(child(n, "guid"));
    s.name = text(child(n, "name"));
    s.sensor_vendor = text(child(n, "sensorVendor"));
    s.sensor_model = text(child(n, "sensorModel"));
    s.sensor_serial = text(child(n, "sensorSerialNumber"));
    s.software_version = text(child(n, "sensorSoftwareVersion"));
    if (const xmlNode* pose = child(n, "pose")) {
        const xmlNode* r = child(pose, "rotation");
        const char* q[4] = {"w", "x", "y", "z"};
        for (int i = 0; i < 4; ++i) s.rotation_wxyz[i] = number(child(r, q[i]), i == 0 ? 1 : 0);
        const xmlNode* t = child(pose, "translation");
        for (int i = 0; i < 3; ++i) s.translation[i] = number(child(t, q[i + 1]), 0.0);
    }
    const xmlNode* points = child(n, "points");
    if (!points) return Status(StatusCode::kProtocolError, where + ": a Data3D has no points");
    auto p = compressedVector(points, where);
    if (!p.isOk()) return p.status();
    s.points = *p;
    if (const xmlNode* t = child(n, "handscan:trajectory")) {
        auto tv = compressedVector(t, where);
        if (!tv.isOk()) return tv.status();
        s.trajectory = *tv;
    }
    return s;
}

}  // namespace

Status parseXml(const std::string& xml, const std::string& where, E57File& file) {
    const std::unique_ptr<xmlDoc, void (*)(xmlDoc*)> doc(
        xmlReadMemory(xml.data(), static_cast<int>(xml.size()), "e57.xml", nullptr,
                      XML_PARSE_NONET | XML_PARSE_NOERROR | XML_PARSE_NOWARNING),
        xmlFreeDoc);
    if (!doc) {
        const xmlError* e = xmlGetLastError();
        return Status(StatusCode::kProtocolError,
                      where + ": the XML section does not parse" +
                          (e && e->message ? std::string(": ") + e->message : std::string()));
    }
    const xmlNode* root = xmlDocGetRootElement(doc.get());
    if (!root || std::string(chars(root->name)) != "e57Root")
        return Status(StatusCode::kProtocolError, where + ": the XML's root is not e57Root");
    file.guid = text(child(root, "guid"));
    const xmlNode* data3d = child(root, "data3D");
    for (const xmlNode* c = data3d ? data3d->children : nullptr; c; c = c->next) {
        if (c->type != XML_ELEMENT_NODE) continue;
        auto s = scan(c, where);
        if (!s.isOk()) return s.status();
        file.scans.push_back(std::move(*s));
    }
    return Status::ok();
}

}  // namespace handscan::exporter::e57
