// registry.h — a small entity-component store: entities are ids, components are plain structs kept in
// one dense array per type (sparse-set layout, as in EnTT), systems are free functions that iterate them.
// Not thread-safe; one registry per simulation. Iteration order is insertion order (deterministic).
#pragma once

#include <cassert>
#include <cstdint>
#include <memory>
#include <typeindex>
#include <unordered_map>
#include <utility>
#include <vector>

namespace engine {

/// An entity handle: an index into the registry. kNoEntity marks "none".
using Entity = uint32_t;
constexpr Entity kNoEntity = UINT32_MAX;

class Registry {
 public:
  /// Creates a new entity with no components.
  Entity create() { return next_++; }

  /// Number of entities ever created.
  uint32_t size() const { return next_; }

  /// Adds (or replaces) component C on e and returns it.
  template <typename C>
  C& add(Entity e, C component) {
    Pool<C>& p = pool<C>();
    if (e >= p.sparse.size()) p.sparse.resize(e + 1, kAbsent);
    if (p.sparse[e] != kAbsent) return p.dense[p.sparse[e]] = std::move(component);
    p.sparse[e] = static_cast<uint32_t>(p.dense.size());
    p.owners.push_back(e);
    p.dense.push_back(std::move(component));
    return p.dense.back();
  }

  /// True if e has component C.
  template <typename C>
  bool has(Entity e) const {
    const Pool<C>* p = find<C>();
    return p && e < p->sparse.size() && p->sparse[e] != kAbsent;
  }

  /// Component C of e; e must have it.
  template <typename C>
  C& get(Entity e) {
    assert(has<C>(e));
    Pool<C>& p = pool<C>();
    return p.dense[p.sparse[e]];
  }
  template <typename C>
  const C& get(Entity e) const {
    assert(has<C>(e));
    const Pool<C>& p = *find<C>();
    return p.dense[p.sparse[e]];
  }

  /// Calls fn(entity, C&, Others&...) for every entity that has C and all Others, in insertion order of C.
  template <typename C, typename... Others, typename Fn>
  void each(Fn&& fn) {
    Pool<C>& p = pool<C>();
    for (size_t i = 0; i < p.dense.size(); ++i) {
      Entity e = p.owners[i];
      if ((has<Others>(e) && ...)) fn(e, p.dense[i], get<Others>(e)...);
    }
  }
  template <typename C, typename... Others, typename Fn>
  void each(Fn&& fn) const {
    const Pool<C>* p = find<C>();
    if (!p) return;
    for (size_t i = 0; i < p->dense.size(); ++i) {
      Entity e = p->owners[i];
      if ((has<Others>(e) && ...)) fn(e, p->dense[i], get<Others>(e)...);
    }
  }

 private:
  static constexpr uint32_t kAbsent = UINT32_MAX;

  struct PoolBase {
    virtual ~PoolBase() = default;
  };
  template <typename C>
  struct Pool final : PoolBase {
    std::vector<C> dense;
    std::vector<Entity> owners;
    std::vector<uint32_t> sparse;
  };

  template <typename C>
  Pool<C>& pool() {
    auto& slot = pools_[std::type_index(typeid(C))];
    if (!slot) slot = std::make_unique<Pool<C>>();
    return static_cast<Pool<C>&>(*slot);
  }
  template <typename C>
  const Pool<C>* find() const {
    auto it = pools_.find(std::type_index(typeid(C)));
    return it == pools_.end() ? nullptr : static_cast<const Pool<C>*>(it->second.get());
  }

  Entity next_ = 0;
  std::unordered_map<std::type_index, std::unique_ptr<PoolBase>> pools_;
};

}  // namespace engine
