// A small reader for FMI 2.0 (and, read_model_description3, FMI 3.0) modelDescription.xml: enough XML (elements, attributes,
// comments, processing instructions, the predefined and numeric entities) to get the GUID,
// the co-simulation model identifier and each ScalarVariable's name, value reference,
// causality, variability, base type and start value.
#pragma once

#include <cstdlib>
#include <fstream>
#include <map>
#include <sstream>
#include <stdexcept>
#include <string>
#include <vector>

namespace harness {

struct XmlElement {
    std::string name;                           // "/Name" for a closing tag
    std::map<std::string, std::string> attrs;
    bool self_closing = false;
};

inline std::string xml_decode(const std::string& s) {
    std::string out;
    for (size_t i = 0; i < s.size(); ++i) {
        if (s[i] != '&') {
            out += s[i];
            continue;
        }
        const size_t semi = s.find(';', i);
        if (semi == std::string::npos) throw std::runtime_error("xml: unterminated entity");
        const std::string ent = s.substr(i + 1, semi - i - 1);
        if (ent == "lt") out += '<';
        else if (ent == "gt") out += '>';
        else if (ent == "amp") out += '&';
        else if (ent == "quot") out += '"';
        else if (ent == "apos") out += '\'';
        else if (!ent.empty() && ent[0] == '#') {
            const unsigned long cp = ent.size() > 1 && (ent[1] == 'x' || ent[1] == 'X')
                                         ? std::strtoul(ent.c_str() + 2, nullptr, 16)
                                         : std::strtoul(ent.c_str() + 1, nullptr, 10);
            // UTF-8 encode
            if (cp < 0x80) {
                out += static_cast<char>(cp);
            } else if (cp < 0x800) {
                out += static_cast<char>(0xC0 | (cp >> 6));
                out += static_cast<char>(0x80 | (cp & 0x3F));
            } else if (cp < 0x10000) {
                out += static_cast<char>(0xE0 | (cp >> 12));
                out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
                out += static_cast<char>(0x80 | (cp & 0x3F));
            } else {
                out += static_cast<char>(0xF0 | (cp >> 18));
                out += static_cast<char>(0x80 | ((cp >> 12) & 0x3F));
                out += static_cast<char>(0x80 | ((cp >> 6) & 0x3F));
                out += static_cast<char>(0x80 | (cp & 0x3F));
            }
        } else {
            throw std::runtime_error("xml: unknown entity &" + ent + ";");
        }
        i = semi;
    }
    return out;
}

// All tags of a document, in order (text content is skipped: FMI 2.0 keeps data in attributes).
inline std::vector<XmlElement> xml_tags(const std::string& doc) {
    std::vector<XmlElement> tags;
    size_t i = 0;
    auto is_space = [](char c) { return c == ' ' || c == '\t' || c == '\n' || c == '\r'; };
    while ((i = doc.find('<', i)) != std::string::npos) {
        if (doc.compare(i, 4, "<!--") == 0) {
            const size_t e = doc.find("-->", i + 4);
            if (e == std::string::npos) throw std::runtime_error("xml: unterminated comment");
            i = e + 3;
            continue;
        }
        if (doc.compare(i, 2, "<?") == 0 || doc.compare(i, 2, "<!") == 0) {
            const size_t e = doc.find('>', i);
            if (e == std::string::npos) throw std::runtime_error("xml: unterminated declaration");
            i = e + 1;
            continue;
        }
        XmlElement el;
        size_t p = i + 1;
        const size_t name_start = p;
        while (p < doc.size() && !is_space(doc[p]) && doc[p] != '>' && doc[p] != '/') ++p;
        if (p < doc.size() && doc[p] == '/' && p == name_start) {  // closing tag "</Name>"
            ++p;
            while (p < doc.size() && !is_space(doc[p]) && doc[p] != '>') ++p;
        }
        el.name = doc.substr(name_start, p - name_start);
        for (;;) {
            while (p < doc.size() && is_space(doc[p])) ++p;
            if (p >= doc.size()) throw std::runtime_error("xml: unterminated tag " + el.name);
            if (doc[p] == '>') {
                ++p;
                break;
            }
            if (doc[p] == '/' && p + 1 < doc.size() && doc[p + 1] == '>') {
                el.self_closing = true;
                p += 2;
                break;
            }
            const size_t an = p;
            while (p < doc.size() && doc[p] != '=' && !is_space(doc[p])) ++p;
            const std::string key = doc.substr(an, p - an);
            while (p < doc.size() && is_space(doc[p])) ++p;
            if (p >= doc.size() || doc[p] != '=') throw std::runtime_error("xml: attribute without value: " + key);
            ++p;
            while (p < doc.size() && is_space(doc[p])) ++p;
            if (p >= doc.size() || (doc[p] != '"' && doc[p] != '\'')) throw std::runtime_error("xml: unquoted attribute " + key);
            const char q = doc[p++];
            const size_t ve = doc.find(q, p);
            if (ve == std::string::npos) throw std::runtime_error("xml: unterminated attribute " + key);
            el.attrs[key] = xml_decode(doc.substr(p, ve - p));
            p = ve + 1;
        }
        tags.push_back(std::move(el));
        i = p;
    }
    return tags;
}

struct ScalarVariable {
    std::string name;
    unsigned int value_reference = 0;
    std::string causality;    // parameter, input, output, local, ...
    std::string variability;  // fixed, tunable, discrete, continuous, ...
    std::string type;         // Real, Integer, Boolean, Enumeration, String
    std::string start;        // empty when absent
    bool has_start = false;
};

struct ModelDescription {
    std::string fmi_version;
    std::string guid;
    std::string model_name;
    std::string cs_model_identifier;  // empty if the FMU has no CoSimulation element
    std::vector<ScalarVariable> variables;
    std::map<std::string, size_t> by_name;

    const ScalarVariable* find(const std::string& name) const {
        auto it = by_name.find(name);
        return it == by_name.end() ? nullptr : &variables[it->second];
    }
    const ScalarVariable& at(const std::string& name) const {
        const ScalarVariable* v = find(name);
        if (!v) throw std::runtime_error("modelDescription.xml has no variable named " + name);
        return *v;
    }
};

inline ModelDescription read_model_description(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::vector<XmlElement> tags = xml_tags(ss.str());

    ModelDescription md;
    bool in_var = false;
    ScalarVariable cur;
    for (const XmlElement& t : tags) {
        if (t.name == "fmiModelDescription") {
            md.fmi_version = t.attrs.count("fmiVersion") ? t.attrs.at("fmiVersion") : "";
            md.guid = t.attrs.count("guid") ? t.attrs.at("guid") : "";
            md.model_name = t.attrs.count("modelName") ? t.attrs.at("modelName") : "";
        } else if (t.name == "CoSimulation") {
            md.cs_model_identifier = t.attrs.count("modelIdentifier") ? t.attrs.at("modelIdentifier") : "";
        } else if (t.name == "ScalarVariable") {
            cur = ScalarVariable{};
            cur.name = t.attrs.at("name");
            cur.value_reference = static_cast<unsigned int>(std::stoul(t.attrs.at("valueReference")));
            cur.causality = t.attrs.count("causality") ? t.attrs.at("causality") : "local";
            cur.variability = t.attrs.count("variability") ? t.attrs.at("variability") : "continuous";
            in_var = !t.self_closing;
        } else if (in_var && (t.name == "Real" || t.name == "Integer" || t.name == "Boolean" ||
                              t.name == "Enumeration" || t.name == "String")) {
            cur.type = t.name;
            auto it = t.attrs.find("start");
            if (it != t.attrs.end()) {
                cur.start = it->second;
                cur.has_start = true;
            }
        } else if (t.name == "/ScalarVariable" && in_var) {
            in_var = false;
            if (md.by_name.count(cur.name)) throw std::runtime_error("duplicate variable " + cur.name);
            md.by_name[cur.name] = md.variables.size();
            md.variables.push_back(cur);
        }
    }
    if (md.guid.empty()) throw std::runtime_error(path + ": no guid attribute");
    return md;
}

// An FMI 3.0 variable: its name, value reference, causality, type element (Float64, Int32,
// Boolean, ...) and number of values (the product of its Dimension starts; 1 for a scalar).
struct Variable3 {
    std::string name;
    unsigned int value_reference = 0;
    std::string causality;
    std::string type;
    size_t size = 1;
};

struct ModelDescription3 {
    std::string fmi_version;
    std::string instantiation_token;
    std::string cs_model_identifier;
    std::map<std::string, Variable3> variables;

    const Variable3& at(const std::string& name) const {
        auto it = variables.find(name);
        if (it == variables.end()) throw std::runtime_error("modelDescription.xml has no variable named " + name);
        return it->second;
    }
};

inline ModelDescription3 read_model_description3(const std::string& path) {
    std::ifstream in(path, std::ios::binary);
    if (!in) throw std::runtime_error("cannot open " + path);
    std::stringstream ss;
    ss << in.rdbuf();
    const std::vector<XmlElement> tags = xml_tags(ss.str());
    ModelDescription3 md;
    bool in_vars = false;
    std::string open;  // the variable whose Dimension children follow
    for (const XmlElement& t : tags) {
        if (t.name == "fmiModelDescription") {
            md.fmi_version = t.attrs.count("fmiVersion") ? t.attrs.at("fmiVersion") : "";
            md.instantiation_token = t.attrs.count("instantiationToken") ? t.attrs.at("instantiationToken") : "";
        } else if (t.name == "CoSimulation") {
            md.cs_model_identifier = t.attrs.count("modelIdentifier") ? t.attrs.at("modelIdentifier") : "";
        } else if (t.name == "ModelVariables") {
            in_vars = true;
        } else if (t.name == "/ModelVariables") {
            in_vars = false;
        } else if (in_vars && t.name == "Dimension" && !open.empty()) {
            md.variables[open].size *= static_cast<size_t>(std::stoul(t.attrs.at("start")));
        } else if (in_vars && !t.name.empty() && t.name[0] != '/' && t.attrs.count("valueReference")) {
            Variable3 v;
            v.name = t.attrs.at("name");
            v.value_reference = static_cast<unsigned int>(std::stoul(t.attrs.at("valueReference")));
            v.causality = t.attrs.count("causality") ? t.attrs.at("causality") : "local";
            v.type = t.name;
            if (md.variables.count(v.name)) throw std::runtime_error("duplicate variable " + v.name);
            md.variables[v.name] = v;
            open = t.self_closing ? std::string() : v.name;
        } else if (in_vars && !t.name.empty() && t.name[0] == '/') {
            open.clear();
        }
    }
    if (md.instantiation_token.empty()) throw std::runtime_error(path + ": no instantiationToken attribute");
    return md;
}

}  // namespace harness
