#pragma once
// Threads standing in for processes in tests of code split over processes (icobrdf/core/projection/row_split_projection.hpp,
// icobrdf/core/fit/sample_fit.hpp SampleFitSplit).
#include <Eigen/Core>

#include <condition_variable>
#include <map>
#include <mutex>
#include <utility>
#include <vector>

#include "icobrdf/core/projection/row_split_projection.hpp"

namespace icobrdf::test {

// An exchange through memory for threads standing in for processes: sums in part order, mailboxes for the
// ring.
class ThreadExchange {
 public:
  explicit ThreadExchange(int parts) : parts_(parts), boxes_(static_cast<size_t>(parts)) {}
  class Part : public RowSplitExchange {
   public:
    Part(ThreadExchange& x, int part) : x_(x), part_(part) {}
    int part() const override { return part_; }
    int parts() const override { return x_.parts_; }
    void sum(std::vector<Eigen::MatrixXd>& m) override { x_.sum(part_, m); }
    Eigen::MatrixXd shift(Eigen::MatrixXd block, bool send, bool receive) override {
      if (send) x_.put((part_ + x_.parts_ - 1) % x_.parts_, std::move(block));
      return receive ? x_.take(part_) : Eigen::MatrixXd();
    }

   private:
    ThreadExchange& x_;
    int part_;
  };

 private:
  void sum(int part, std::vector<Eigen::MatrixXd>& m) {
    std::unique_lock<std::mutex> lock(mutex_);
    const long round = round_;
    contributions_[part] = m;
    if (static_cast<int>(contributions_.size()) == parts_) {
      result_ = contributions_[0];
      for (int p = 1; p < parts_; ++p)
        for (size_t k = 0; k < result_.size(); ++k) result_[k] += contributions_[p][k];
      last_contributions_ = std::move(contributions_);
      contributions_.clear();
      ++round_;
      changed_.notify_all();
    } else {
      changed_.wait(lock, [&] { return round_ != round; });
    }
    m = result_;
  }

 public:
  // Sums completed so far.
  long rounds() {
    std::lock_guard<std::mutex> lock(mutex_);
    return round_;
  }

 private:
  void put(int to, Eigen::MatrixXd block) {
    std::lock_guard<std::mutex> lock(mutex_);
    boxes_[static_cast<size_t>(to)].push_back(std::move(block));
    changed_.notify_all();
  }
  Eigen::MatrixXd take(int part) {
    std::unique_lock<std::mutex> lock(mutex_);
    auto& box = boxes_[static_cast<size_t>(part)];
    changed_.wait(lock, [&] { return !box.empty(); });
    Eigen::MatrixXd b = std::move(box.front());
    box.erase(box.begin());
    return b;
  }
  int parts_;
  std::mutex mutex_;
  std::condition_variable changed_;
  long round_ = 0;
  std::map<int, std::vector<Eigen::MatrixXd>> contributions_;

 public:
  std::map<int, std::vector<Eigen::MatrixXd>> last_contributions_;  // of the last sum, by part

 private:
  std::vector<Eigen::MatrixXd> result_;
  std::vector<std::vector<Eigen::MatrixXd>> boxes_;
};

}  // namespace icobrdf::test
