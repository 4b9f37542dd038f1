// Every setting is described once: name, unit, range, default, help, and the struct field it
// fills. The same table drives the command line (--set module.key=value), JSON settings files,
// the editor panel, the typed structs the passes read (fromSettings) and the tests.
#pragma once

#include <nlohmann/json.hpp>

#include <algorithm>
#include <filesystem>
#include <functional>
#include <map>
#include <stdexcept>
#include <string>
#include <type_traits>
#include <utility>
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

// ---- rows bound to struct fields --------------------------------------------------------------
// A typed settings struct (ReflectionSettings, RendererOptions) names each field once, in a row
// of its table that binds the field: fromSettings() fills the struct and the struct takes its
// defaults from the same rows, so no second list of names or defaults can drift from the table.

namespace detail {
template <class T>
struct MemberOf;
template <class S, class F>
struct MemberOf<F S::*> {
    using Struct = S;
    using Field = F;
};
// One address per bound member: how a struct's default finds its row.
template <auto Member>
inline constexpr char kMemberTag = 0;

template <class F>
F toField(double v) {
    if constexpr (std::is_same_v<F, bool>)
        return v != 0.0;
    else if constexpr (std::is_enum_v<F>)
        return static_cast<F>(static_cast<std::underlying_type_t<F>>(v));
    else
        return static_cast<F>(v);
}
template <class F>
double fromField(F f) {
    if constexpr (std::is_enum_v<F>)
        return static_cast<double>(static_cast<std::underlying_type_t<F>>(f));
    else
        return static_cast<double>(f);
}
template <class F>
bool fits(const SettingDesc& d) {
    if constexpr (std::is_same_v<F, bool>)
        // An Enum of two choices may read as a switch (reflections.cmo_unresolved=pass_behind).
        return d.type == SettingType::Bool || (d.type == SettingType::Enum && d.choices.size() == 2);
    else if constexpr (std::is_enum_v<F>)
        return d.type == SettingType::Enum;
    else if constexpr (std::is_floating_point_v<F>)
        return d.type == SettingType::Float;
    else
        return d.type == SettingType::Int;
}
}  // namespace detail

template <class S>
struct SettingField {
    SettingDesc desc;
    const void* tag = nullptr;  // &detail::kMemberTag<Member>
    std::function<void(S&, double)> write;
    std::function<double(const S&)> read;  // the field as the setting's value (tests)
};

// A row of S's table whose field `access` reaches, a generic lambda returning a reference to it
// (`[](auto& m) -> auto& { return m.baseColor.r; }`), for fields a member pointer cannot name. A
// field whose type does not fit the setting's (an int field on a Float) is a logic_error; an Enum
// value beyond the choices is clamped to them (values from a Settings never are).
template <class S, class Access>
SettingField<S> bindAccess(SettingDesc desc, Access access, const void* tag = nullptr) {
    using F = std::remove_cvref_t<decltype(access(std::declval<S&>()))>;
    if (!detail::fits<F>(desc)) throw std::logic_error("setting '" + desc.name + "' is bound to a field of another type");
    double last = desc.choices.empty() ? 0.0 : double(desc.choices.size() - 1);
    auto write = [access, last](S& s, double v) {
        if constexpr (std::is_enum_v<F>) v = std::clamp(v, 0.0, last);
        access(s) = detail::toField<F>(v);
    };
    return {std::move(desc), tag, write, [access](const S& s) { return detail::fromField(access(s)); }};
}

// A row of S's table: `bind<&ReflectionSettings::temporalAlpha>({"reflections.temporal_alpha",
// ...})`.
template <auto Member>
SettingField<typename detail::MemberOf<decltype(Member)>::Struct> bind(SettingDesc desc) {
    using S = typename detail::MemberOf<decltype(Member)>::Struct;
    return bindAccess<S>(std::move(desc), [](auto& s) -> auto& { return s.*Member; }, &detail::kMemberTag<Member>);
}

// The table of a settings struct, in the order of the table (README, --help, editor panels).
template <class S>
class SettingFields {
public:
    explicit SettingFields(std::vector<SettingField<S>> rows) : rows_(std::move(rows)) {}
    const std::vector<SettingField<S>>& rows() const { return rows_; }

    std::vector<SettingDesc> descs() const {
        std::vector<SettingDesc> out;
        for (const SettingField<S>& r : rows_) out.push_back(r.desc);
        return out;
    }
    void write(const Settings& settings, S& s) const {
        for (const SettingField<S>& r : rows_) r.write(s, settings.get(r.desc.name));
    }
    void writeDefaults(S& s) const {
        for (const SettingField<S>& r : rows_) r.write(s, r.desc.defaultValue);
    }
    // The rows again, on the member `outer` of a struct that holds an S
    // (RendererOptions::environment).
    template <class Outer>
    std::vector<SettingField<Outer>> within(S Outer::*outer) const {
        std::vector<SettingField<Outer>> out;
        for (const SettingField<S>& r : rows_)
            out.push_back({r.desc, r.tag, [w = r.write, outer](Outer& o, double v) { w(o.*outer, v); },
                           [rd = r.read, outer](const Outer& o) { return rd(o.*outer); }});
        return out;
    }
    double defaultOf(const void* tag) const {
        for (const SettingField<S>& r : rows_)
            if (r.tag == tag) return r.desc.defaultValue;
        throw std::logic_error("a settings default was asked of a field its table does not bind");
    }

private:
    std::vector<SettingField<S>> rows_;
};

// The struct S (which declares `static const SettingFields<S>& fields();`) filled from `settings`.
template <class S>
S fromSettings(const Settings& settings) {
    S s;
    S::fields().write(settings, s);
    return s;
}

// The table's default of one field, for an aggregate's member initializer, which keeps it an
// aggregate (`{.cubeSize = 8}` still works): `uint32_t cubeSize = settingDefault<&X::cubeSize>();`.
template <auto Member>
typename detail::MemberOf<decltype(Member)>::Field settingDefault() {
    using M = detail::MemberOf<decltype(Member)>;
    return detail::toField<typename M::Field>(M::Struct::fields().defaultOf(&detail::kMemberTag<Member>));
}

}  // namespace speculum
