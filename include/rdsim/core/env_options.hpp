#pragma once
#include <concepts>
#include <memory>
#include <nlohmann/json.hpp>
#include <type_traits>
#include <typeinfo>
#include <utility>
#include <vector>

#include "rdsim/core/config_fields.hpp"
#include "rdsim/core/config_reader.hpp"

namespace rdsim {

// One group of an env's own options, held by value: any struct with a describe()
// (core/config_fields.hpp), declared next to the env that reads it (envs/reach_options.hpp: the
// reaching tasks' options; envs/obstacle_options.hpp: jaka_obstacle's column and reward). An env
// lists the groups it reads in its published defaults (EnvConfig::options); the registry reads,
// writes, checks and documents a config's "env" keys through them, so each key is declared once,
// in its group's describe(). Copies are deep.
class EnvOptions {
public:
  template <class T>
    requires(!std::same_as<std::remove_cvref_t<T>, EnvOptions>)
  explicit EnvOptions(T value) : self_(std::make_unique<Model<T>>(std::move(value))) {}
  EnvOptions(const EnvOptions& other) : self_(other.self_ ? other.self_->clone() : nullptr) {}
  EnvOptions& operator=(const EnvOptions& other) {
    if (this != &other) self_ = other.self_ ? other.self_->clone() : nullptr;
    return *this;
  }
  EnvOptions(EnvOptions&&) noexcept = default;
  EnvOptions& operator=(EnvOptions&&) noexcept = default;

  // The group's struct, or nullptr when it holds another type.
  template <class T>
  T* get() {
    return self_->type() == typeid(T) ? &static_cast<Model<T>&>(*self_).value : nullptr;
  }
  template <class T>
  const T* get() const {
    return self_->type() == typeid(T) ? &static_cast<const Model<T>&>(*self_).value : nullptr;
  }
  const std::type_info& type() const { return self_->type(); }

  // Reads the group's keys from `reader` over the values held (no finish(): the caller's reader
  // checks the keys nobody read).
  void read(ConfigReader& reader) { self_->read(reader); }
  // Adds the group's keys with their values to `out`.
  void write(nlohmann::json& out) const { self_->write(out); }
  // The group's keys, with the values held as defaults.
  std::vector<config::FieldDoc> document() const { return self_->document(); }

private:
  struct Concept {
    virtual ~Concept() = default;
    virtual std::unique_ptr<Concept> clone() const = 0;
    virtual const std::type_info& type() const = 0;
    virtual void read(ConfigReader& reader) = 0;
    virtual void write(nlohmann::json& out) const = 0;
    virtual std::vector<config::FieldDoc> document() const = 0;
  };
  template <class T>
  struct Model final : Concept {
    explicit Model(T v) : value(std::move(v)) {}
    std::unique_ptr<Concept> clone() const override { return std::make_unique<Model>(value); }
    const std::type_info& type() const override { return typeid(T); }
    void read(ConfigReader& reader) override {
      config::FieldReader v(reader);
      describe(v, value);
    }
    void write(nlohmann::json& out) const override {
      config::FieldWriter w(out);
      describe(w, value);
    }
    std::vector<config::FieldDoc> document() const override { return config::document_fields(value); }
    T value;
  };
  std::unique_ptr<Concept> self_;
};

}  // namespace rdsim
