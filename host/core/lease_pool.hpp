// LeasePool: objects that one thread at a time may use (a muParser parser bound to its own x and y),
// lent to the threads of a parallel loop and kept for the next loop, so that each is made once per
// thread that ever needed one rather than once per call.
#pragma once
#include <functional>
#include <memory>
#include <mutex>
#include <utility>
#include <vector>

namespace pdmesh {

template <class T>
class LeasePool {
 public:
  explicit LeasePool(std::function<std::unique_ptr<T>()> make) : make_(std::move(make)) {}
  LeasePool(const LeasePool&) = delete;
  LeasePool& operator=(const LeasePool&) = delete;

  // One object, the caller's alone until the lease ends; default-constructed empty (a loop's
  // per-thread scratch takes one on its first index).
  class Lease {
   public:
    Lease() = default;
    Lease(LeasePool* pool, std::unique_ptr<T> object) : pool_(pool), object_(std::move(object)) {}
    Lease(Lease&& other) noexcept = default;
    Lease& operator=(Lease&& other) noexcept {
      give_back();
      pool_ = other.pool_;
      object_ = std::move(other.object_);
      return *this;
    }
    ~Lease() { give_back(); }
    explicit operator bool() const { return object_ != nullptr; }
    T& operator*() const { return *object_; }
    T* operator->() const { return object_.get(); }

   private:
    void give_back() {
      if (object_) pool_->give_back(std::move(object_));
    }
    LeasePool* pool_ = nullptr;
    std::unique_ptr<T> object_;
  };

  // A kept object if one is free, else a new one from `make` (which may throw; nothing is lent then).
  Lease take() {
    {
      const std::lock_guard<std::mutex> lock(mutex_);
      if (!free_.empty()) {
        std::unique_ptr<T> object = std::move(free_.back());
        free_.pop_back();
        return Lease(this, std::move(object));
      }
    }
    return Lease(this, make_());
  }

 private:
  void give_back(std::unique_ptr<T> object) {
    const std::lock_guard<std::mutex> lock(mutex_);
    free_.push_back(std::move(object));
  }

  std::function<std::unique_ptr<T>()> make_;
  std::mutex mutex_;
  std::vector<std::unique_ptr<T>> free_;
};

}  // namespace pdmesh
