#pragma once
// The study's work items, in serial order: each part-1 configuration, then each extreme case x size
// x configuration. A shard (--shard K/N) runs the items i with i % N == K - 1; every row carries
// its serial number, so the shards' rows merge back into the serial run's order.

namespace study {

struct WorkItems {
    int shard = 1, shards = 1;
    long item = -1;
    // Whether the next item is this shard's.
    bool mine() { return ++item % shards == shard - 1; }
};

}  // namespace study
