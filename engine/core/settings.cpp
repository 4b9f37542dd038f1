#include "speculum/settings.hpp"

#include "speculum/core.hpp"
#include "speculum/limits.hpp"

#include <charconv>
#include <cmath>
#include <fstream>
#include <sstream>

namespace speculum {
namespace {

std::string rangeText(const SettingDesc& d) {
    std::ostringstream s;
    if (d.type == SettingType::Bool) return "true or false";
    if (d.type == SettingType::Enum) {
        for (size_t i = 0; i < d.choices.size(); ++i) s << (i ? ", " : "") << d.choices[i];
        return s.str();
    }
    s << d.min << " .. " << d.max;
    return s.str();
}

}  // namespace

Settings::Settings(std::vector<SettingDesc> table) : table_(std::move(table)) {
    for (const SettingDesc& d : table_) values_[d.name] = d.defaultValue;
}

const SettingDesc* Settings::find(const std::string& name) const {
    for (const SettingDesc& d : table_)
        if (d.name == name) return &d;
    return nullptr;
}

double Settings::get(const std::string& name) const {
    auto it = values_.find(name);
    if (it == values_.end()) throw std::logic_error("no setting named '" + name + "' in the table");
    return it->second;
}

const std::string& Settings::getChoice(const std::string& name) const {
    const SettingDesc* d = find(name);
    if (!d || d->type != SettingType::Enum) throw std::logic_error("'" + name + "' is not an enum setting");
    return d->choices.at(static_cast<size_t>(get(name)));
}

void Settings::set(const std::string& name, double value) {
    const SettingDesc* d = find(name);
    if (!d) {
        std::string known;
        for (const SettingDesc& x : table_) known += (known.empty() ? "" : ", ") + x.name;
        throw argumentError("unknown setting '" + name + "' (known: " + known + ")");
    }
    bool integral = d->type != SettingType::Float;
    if (!std::isfinite(value) || value < d->min || value > d->max || (integral && value != std::floor(value)))
        throw argumentError("setting '" + name + "' must be in " + rangeText(*d));
    values_[name] = value;
}

void Settings::set(const std::string& name, const std::string& text) {
    const SettingDesc* d = find(name);
    if (!d) return set(name, 0.0);  // reports the unknown key
    if (d->type == SettingType::Enum) {
        for (size_t i = 0; i < d->choices.size(); ++i)
            if (d->choices[i] == text) return set(name, static_cast<double>(i));
        throw argumentError("setting '" + name + "' must be one of " + rangeText(*d) + ", not '" + text + "'");
    }
    if (d->type == SettingType::Bool) {
        if (text == "true" || text == "1" || text == "on") return set(name, 1.0);
        if (text == "false" || text == "0" || text == "off") return set(name, 0.0);
        throw argumentError("setting '" + name + "' must be true or false, not '" + text + "'");
    }
    // Plain decimal only: std::stod also took "0x10", " 5", "inf" and "nan" (issue 15).
    double v = 0.0;
    const char* end = text.data() + text.size();
    auto [ptr, ec] = std::from_chars(text.data(), end, v, std::chars_format::general);
    if (text.empty() || ec != std::errc() || ptr != end)
        throw argumentError("setting '" + name + "' needs a number in " + rangeText(*d) + ", not '" + text + "'");
    set(name, v);
}

void Settings::assign(const std::string& kv) {
    size_t eq = kv.find('=');
    if (eq == std::string::npos || eq == 0) throw argumentError("--set needs KEY=VALUE, got '" + kv + "'");
    set(kv.substr(0, eq), kv.substr(eq + 1));
}

void Settings::fromJson(const nlohmann::json& j, const std::string& source) {
    if (!j.is_object()) throw inputError(source, "settings must be a JSON object of \"key\": value");
    for (const auto& [key, value] : j.items()) {
        try {
            // The JSON type must match the setting's: a choice by name, a switch by true/false, a
            // number by a number (true used to pick choice 1 of an enum, "0x10" a number).
            const SettingDesc* d = find(key);
            if (!d) set(key, 0.0);  // reports the unknown key
            const char* want = d->type == SettingType::Enum   ? "one of "
                               : d->type == SettingType::Bool ? "true or false"
                                                              : "a number in ";
            bool ok = d->type == SettingType::Enum   ? value.is_string()
                      : d->type == SettingType::Bool ? value.is_boolean()
                                                     : value.is_number();
            if (!ok) {
                std::string range = d->type == SettingType::Bool ? "" : rangeText(*d);
                throw argumentError("setting '" + key + "' needs " + want + range + ", not " +
                                    value.dump().substr(0, 40));
            }
            if (value.is_string())
                set(key, value.get<std::string>());
            else
                set(key, value.is_boolean() ? (value.get<bool>() ? 1.0 : 0.0) : value.get<double>());
        } catch (const Error& e) {
            throw inputError(source, e.what());
        }
    }
}

void Settings::load(const std::filesystem::path& file) {
    // Regular files only, depth-checked; json::parse (unlike operator>>) rejects text after the
    // object.
    std::string text = limits::readJsonText(file, "settings file");
    nlohmann::json j;
    try {
        j = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
        throw inputError(file.string(), std::string("not valid JSON: ") + e.what());
    }
    fromJson(j, file.string());
}

nlohmann::json Settings::toJson() const {
    nlohmann::json j = nlohmann::json::object();
    for (const SettingDesc& d : table_) {
        double v = values_.at(d.name);
        if (d.type == SettingType::Enum)
            j[d.name] = d.choices.at(static_cast<size_t>(v));
        else if (d.type == SettingType::Bool)
            j[d.name] = v != 0.0;
        else if (d.type == SettingType::Int)
            j[d.name] = static_cast<long long>(v);
        else
            j[d.name] = v;
    }
    return j;
}

std::string Settings::markdownTable() const {
    std::ostringstream s;
    s << "| setting | unit | range | default | help |\n|---|---|---|---|---|\n";
    for (const SettingDesc& d : table_) {
        std::string def = d.type == SettingType::Enum   ? d.choices.at(static_cast<size_t>(d.defaultValue))
                          : d.type == SettingType::Bool ? (d.defaultValue != 0.0 ? "true" : "false")
                                                        : (std::ostringstream() << d.defaultValue).str();
        s << "| `" << d.name << "` | " << d.unit << " | " << rangeText(d) << " | " << def << " | " << d.help << " |\n";
    }
    return s.str();
}

}  // namespace speculum
