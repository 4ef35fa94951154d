// Work run ahead of its turn on other threads, for verification (§4): the clusters are
// verified one at a time, most votes first, but a verification depends on the ones before
// it only through what they found, so the next few can run meanwhile and be settled in
// their turn (Verifier::Speculation in detection.cpp).  Beyond the paper, for speed.
//
// The calling thread hands out indices and takes each result in its turn; worker threads
// run what was handed out, lowest index first.  There is no barrier: a slow task holds up
// its own turn only, while the workers go on with the next ones.  (Batches of tasks run
// with an OpenMP loop wait for their slowest: measured on the speed benchmark's scan, the
// two threads were busy 77 % of verification's wall time.)
#pragma once

#include <condition_variable>
#include <cstddef>
#include <exception>
#include <functional>
#include <map>
#include <mutex>
#include <optional>
#include <thread>
#include <vector>

namespace symmetry {

template <class Result>
class Lookahead {
public:
    /// The work for an index, run by `worker`: 0 is the calling thread, 1 .. workers the
    /// worker threads (each may keep its own scratch space, indexed by it).
    using Task = std::function<Result(size_t index, size_t worker)>;

    /// `workers` threads besides the caller (0: everything runs on the caller, in take()).
    Lookahead(size_t workers, Task task) : task_(std::move(task)) {
        for (size_t w = 1; w <= workers; ++w) threads_.emplace_back([this, w] { work(w); });
    }
    /// Waits for the tasks running; drops the rest.
    ~Lookahead() {
        {
            std::unique_lock<std::mutex> lock(mutex_);
            stop_ = true;
        }
        changed_.notify_all();
        for (std::thread& t : threads_) t.join();
    }
    Lookahead(const Lookahead&) = delete;
    Lookahead& operator=(const Lookahead&) = delete;

    size_t workers() const { return threads_.size(); }

    /// Queues the index for a worker (nothing if it is queued, running or done already).
    void hand_out(size_t index) {
        {
            std::unique_lock<std::mutex> lock(mutex_);
            if (!entries_.emplace(index, Entry{}).second) return;
        }
        changed_.notify_all();
    }

    /// The indices handed out and not taken yet, from `first` on, in order.
    std::vector<size_t> handed_out_from(size_t first) const {
        std::unique_lock<std::mutex> lock(mutex_);
        std::vector<size_t> out;
        for (auto it = entries_.lower_bound(first); it != entries_.end(); ++it)
            if (!it->second.abandoned) out.push_back(it->first);
        return out;
    }

    /// The result for the index, if it was handed out: waits while a worker runs it (the
    /// caller runs the queued ones meanwhile), runs it on the caller if no worker began it.
    /// Nothing if it was not handed out.  A task's exception is thrown here.
    std::optional<Result> take(size_t index) {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            auto it = entries_.find(index);
            if (it == entries_.end() || it->second.abandoned) return std::nullopt;
            Entry& entry = it->second;
            if (entry.state == State::Done) {
                std::optional<Result> result = std::move(entry.result);
                const std::exception_ptr failure = entry.failure;
                entries_.erase(it);
                if (failure) std::rethrow_exception(failure);
                return result;
            }
            // The index itself if no worker has begun it, else the next queued one.
            const size_t next = entry.state == State::Queued ? index : first_queued();
            if (next != kNone) {
                run(next, 0, lock);
                continue;
            }
            changed_.wait(lock);
        }
    }

    /// Forgets the index: its result, once done, is not wanted.
    void drop(size_t index) {
        std::unique_lock<std::mutex> lock(mutex_);
        auto it = entries_.find(index);
        if (it == entries_.end()) return;
        if (it->second.state == State::Running) it->second.abandoned = true;
        else entries_.erase(it);
    }

    /// Waits for the tasks running and forgets everything: the task's inputs may change.
    void clear() {
        std::unique_lock<std::mutex> lock(mutex_);
        for (auto& [index, entry] : entries_) entry.abandoned = true;
        changed_.wait(lock, [this] { return running_ == 0; });
        entries_.clear();
    }

private:
    enum class State { Queued, Running, Done };
    struct Entry {
        State state = State::Queued;
        bool abandoned = false;  // dropped while running: erased when done
        std::optional<Result> result;
        std::exception_ptr failure;
    };
    static constexpr size_t kNone = size_t(-1);

    size_t first_queued() const {
        for (const auto& [index, entry] : entries_)
            if (entry.state == State::Queued && !entry.abandoned) return index;
        return kNone;
    }

    // Runs the queued task `index` on `worker` with the lock released; records its result.
    void run(size_t index, size_t worker, std::unique_lock<std::mutex>& lock) {
        entries_[index].state = State::Running;
        ++running_;
        lock.unlock();
        std::optional<Result> result;
        std::exception_ptr failure;
        try {
            result = task_(index, worker);
        } catch (...) {
            failure = std::current_exception();  // an exception must not leave a thread
        }
        lock.lock();
        --running_;
        Entry& entry = entries_[index];
        if (entry.abandoned) {
            entries_.erase(index);
        } else {
            entry.state = State::Done;
            entry.result = std::move(result);
            entry.failure = failure;
        }
        changed_.notify_all();
    }

    void work(size_t worker) {
        std::unique_lock<std::mutex> lock(mutex_);
        for (;;) {
            changed_.wait(lock, [this] { return stop_ || first_queued() != kNone; });
            if (stop_) return;
            run(first_queued(), worker, lock);
        }
    }

    Task task_;
    mutable std::mutex mutex_;
    std::condition_variable changed_;  // a task handed out or done, or stop
    std::map<size_t, Entry> entries_;
    size_t running_ = 0;
    bool stop_ = false;
    std::vector<std::thread> threads_;  // last: started once the rest is built
};

}  // namespace symmetry
