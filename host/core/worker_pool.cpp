// WorkerPool: helper threads started once; one job at a time, handed out under a mutex.
#include "core/worker_pool.hpp"

#include <unistd.h>

#include <algorithm>

namespace pdmesh {

WorkerPool& WorkerPool::instance() {
  // Never destroyed: its helpers sleep until the process ends. A destructor run at exit would have to
  // join them, and in a child made by fork() (Python's multiprocessing) they do not exist.
  static WorkerPool* const pool = new WorkerPool(std::max(1u, std::thread::hardware_concurrency()) - 1);
  return *pool;
}

WorkerPool::WorkerPool(std::size_t helpers) : pid_(getpid()) {
  threads_.reserve(helpers);
  for (std::size_t k = 0; k < helpers; ++k) threads_.emplace_back(&WorkerPool::work, this, k + 1);
}

WorkerPool::~WorkerPool() {
  {
    const std::lock_guard<std::mutex> lock(mutex_);
    stop_ = true;
  }
  wake_.notify_all();
  for (std::thread& t : threads_) t.join();
}

bool WorkerPool::run(std::size_t count, const std::function<void(std::size_t)>& job) {
  // After fork() the helpers stayed behind in the parent: the child's calls make their own threads.
  if (count > threads_.size() || getpid() != pid_) return false;
  bool idle = false;
  if (!busy_.compare_exchange_strong(idle, true, std::memory_order_acquire)) return false;
  struct Release {
    std::atomic<bool>& busy;
    ~Release() { busy.store(false, std::memory_order_release); }
  } release{busy_};
  std::unique_lock<std::mutex> lock(mutex_);
  job_ = &job;
  count_ = count;
  pending_ = count;
  ++generation_;
  lock.unlock();
  if (count > 0) wake_.notify_all();
  job(0);
  lock.lock();
  done_.wait(lock, [this] { return pending_ == 0; });
  job_ = nullptr;
  return true;
}

void WorkerPool::work(std::size_t index) {
  std::size_t seen = 0;
  std::unique_lock<std::mutex> lock(mutex_);
  for (;;) {
    wake_.wait(lock, [&] { return stop_ || generation_ != seen; });
    if (stop_) return;
    seen = generation_;
    if (index > count_) continue;  // not needed for this job
    const std::function<void(std::size_t)>* job = job_;
    lock.unlock();
    (*job)(index);
    lock.lock();
    if (--pending_ == 0) done_.notify_one();
  }
}

void start_workers() { (void)WorkerPool::instance(); }

}  // namespace pdmesh
