// Every setting is described once: name, unit, range, default, help. The same table drives the
// command line (--set module.key=value), JSON settings files, the editor panel and the tests.
#pragma once

#include <nlohmann/json.hpp>

#include <filesystem>
#include <map>
#include <string>
#include <vector>

namespace speculum {

enum class SettingType { Float, Int, Bool, Enum };

struct SettingDesc {
    std::string name;   // "module.key", e.g. "render.exposure"
    SettingType type = SettingType::Float;
    std::string unit;   // "ms", "px", "EV", "" for plain numbers
    double min = 0.0;
    double max = 1.0;
    double defaultValue = 0.0;
    std::vector<std::string> choices;  // Enum: value is the index into choices
    std::string help;
};

// Values of the settings of one table; lookups by a name the table lacks are programming errors.
class Settings {
public:
    explicit Settings(std::vector<SettingDesc> table);
    const std::vector<SettingDesc>& table() const { return table_; }
    const SettingDesc* find(const std::string& name) const;

    double get(const std::string& name) const;
    float getFloat(const std::string& name) const { return static_cast<float>(get(name)); }
    int getInt(const std::string& name) const { return static_cast<int>(get(name)); }
    bool getBool(const std::string& name) const { return get(name) != 0.0; }
    const std::string& getChoice(const std::string& name) const;

    // Parses and range-checks; throws Error(BadArguments) naming the key for an unknown key or a
    // bad value (with the valid range or choices).
    void set(const std::string& name, const std::string& value);
    void set(const std::string& name, double value);
    // "key=value"
    void assign(const std::string& keyEqualsValue);

    // JSON: {"render.exposure": 1.0, "reflections.trace": "hiz"}. load() throws
    // Error(BadInput) naming the file for unreadable JSON, unknown keys or bad values.
    void load(const std::filesystem::path& file);
    void fromJson(const nlohmann::json& j, const std::string& source);
    nlohmann::json toJson() const;
    // Markdown table of the settings (name, unit, range, default, help) for READMEs.
    std::string markdownTable() const;

private:
    std::vector<SettingDesc> table_;
    std::map<std::string, double> values_;
};

}  // namespace speculum
