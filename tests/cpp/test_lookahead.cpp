// Lookahead (lookahead.h): work handed out ahead of its turn and taken in turn.  Its
// oracle is the work run in turn on the calling thread: the results must be the same,
// whoever ran them, in whatever order they finished.
#include "core/lookahead.h"

#include <gtest/gtest.h>

#include <atomic>
#include <chrono>
#include <stdexcept>
#include <thread>

using namespace symmetry;

namespace {
// A task whose result depends on its index alone, slow for some indices so that tasks
// finish out of order.
size_t square_after_a_while(size_t index) {
    if (index % 3 == 0) std::this_thread::sleep_for(std::chrono::milliseconds(5));
    return index * index;
}
}  // namespace

TEST(Lookahead, ResultsTakenInTurnAreTheTasksWhoeverRanThem) {
    for (size_t workers : {0, 1, 3}) {
        std::atomic<int> on_workers{0};
        Lookahead<size_t> ahead(workers, [&](size_t index, size_t worker) {
            if (worker != 0) ++on_workers;
            EXPECT_LE(worker, workers);
            return square_after_a_while(index);
        });
        EXPECT_EQ(ahead.workers(), workers);
        for (size_t i = 0; i < 40; ++i) {
            for (size_t j = i; j < i + 4; ++j) ahead.hand_out(j);  // again: no effect
            const std::optional<size_t> result = ahead.take(i);
            ASSERT_TRUE(result.has_value());
            EXPECT_EQ(*result, i * i);
        }
        if (workers == 0) EXPECT_EQ(on_workers, 0);
    }
}

TEST(Lookahead, WhatWasNotHandedOutOrWasDroppedGivesNothing) {
    std::atomic<int> runs{0};
    Lookahead<size_t> ahead(1, [&](size_t index, size_t) {
        ++runs;
        return index;
    });
    EXPECT_FALSE(ahead.take(5).has_value());  // never handed out
    ahead.hand_out(7);
    ahead.drop(7);
    EXPECT_FALSE(ahead.take(7).has_value());
    ahead.hand_out(8);
    ahead.hand_out(9);
    EXPECT_EQ(ahead.handed_out_from(8), (std::vector<size_t>{8, 9}));
    EXPECT_EQ(ahead.handed_out_from(9), (std::vector<size_t>{9}));
    ahead.clear();
    EXPECT_TRUE(ahead.handed_out_from(0).empty());
    EXPECT_FALSE(ahead.take(8).has_value());
    EXPECT_LE(runs, 3);
}

// clear() waits for the tasks running: the caller may then change what they read.
TEST(Lookahead, ClearWaitsForTheTasksRunning) {
    std::vector<size_t> inputs(16, 1);
    Lookahead<size_t> ahead(2, [&](size_t index, size_t) {
        std::this_thread::sleep_for(std::chrono::milliseconds(2));
        return inputs[index];
    });
    for (size_t i = 0; i < 16; ++i) ahead.hand_out(i);
    std::this_thread::sleep_for(std::chrono::milliseconds(1));
    ahead.clear();
    inputs.assign(16, 2);  // no task may read the old inputs any more
    for (size_t i = 0; i < 16; ++i) ahead.hand_out(i);
    for (size_t i = 0; i < 16; ++i) EXPECT_EQ(ahead.take(i), std::optional<size_t>(2));
}

TEST(Lookahead, ATasksExceptionIsThrownWhereItsResultIsTaken) {
    Lookahead<size_t> ahead(1, [](size_t index, size_t) -> size_t {
        if (index == 2) throw std::runtime_error("two");
        return index;
    });
    for (size_t i = 0; i < 4; ++i) ahead.hand_out(i);
    EXPECT_EQ(ahead.take(0), std::optional<size_t>(0));
    EXPECT_EQ(ahead.take(1), std::optional<size_t>(1));
    EXPECT_THROW(ahead.take(2), std::runtime_error);
    EXPECT_EQ(ahead.take(3), std::optional<size_t>(3));
}
