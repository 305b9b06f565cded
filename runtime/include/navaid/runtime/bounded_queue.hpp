#pragma once
// A bounded queue between two pipeline threads. When it is full, push() either waits for room
// (replay: nothing is lost, so a threaded replay sees what a single thread would) or drops the
// oldest item (real time: the newest sensor data matters most), counting the drops. close() ends
// it: pop() returns the items left, then nothing.
#include <condition_variable>
#include <cstddef>
#include <deque>
#include <mutex>
#include <optional>

namespace navaid::runtime {

template <class T>
class BoundedQueue {
 public:
  BoundedQueue(std::size_t capacity, bool drop_oldest) : capacity_(capacity), drop_oldest_(drop_oldest) {}

  /// False when the queue was closed (the item is not taken).
  bool push(T item) {
    std::unique_lock<std::mutex> lock(m_);
    if (!drop_oldest_) room_.wait(lock, [&] { return closed_ || items_.size() < capacity_; });
    if (closed_) return false;
    if (items_.size() >= capacity_) {
      items_.pop_front();
      ++dropped_;
    }
    items_.push_back(std::move(item));
    max_depth_ = std::max(max_depth_, items_.size());
    ready_.notify_one();
    return true;
  }

  /// The oldest item; waits for one; nullopt once closed and empty.
  std::optional<T> pop() {
    std::unique_lock<std::mutex> lock(m_);
    ready_.wait(lock, [&] { return closed_ || !items_.empty(); });
    if (items_.empty()) return std::nullopt;
    T item = std::move(items_.front());
    items_.pop_front();
    room_.notify_one();
    return item;
  }

  /// No more pushes; pop() drains what is left. `discard`: drop it instead (after an error).
  void close(bool discard = false) {
    std::lock_guard<std::mutex> lock(m_);
    closed_ = true;
    if (discard) items_.clear();
    ready_.notify_all();
    room_.notify_all();
  }

  std::size_t dropped() const {
    std::lock_guard<std::mutex> lock(m_);
    return dropped_;
  }
  std::size_t max_depth() const {
    std::lock_guard<std::mutex> lock(m_);
    return max_depth_;
  }
  std::size_t capacity() const { return capacity_; }

 private:
  const std::size_t capacity_;
  const bool drop_oldest_;
  mutable std::mutex m_;
  std::condition_variable ready_, room_;
  std::deque<T> items_;
  bool closed_ = false;
  std::size_t dropped_ = 0, max_depth_ = 0;
};

}  // namespace navaid::runtime
