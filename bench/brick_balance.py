#!/usr/bin/python3
"""bench/brick_balance.py — load balance of a bricked run at 10-1000 ranks, simulated from the
per-brick costs of a real run (`fortu run ... --brick-times costs.csv`, docs/scaling.md).

  brick_balance.py costs.csv [RANKS...]

For each rank count R it replays the bricks two ways: the shared counter fortu uses (each
rank takes the next brick when it is free: greedy list scheduling in brick order) and a
static split (brick b to rank b mod R). It prints the makespan over the ideal sum/R (1.00 is
perfect balance), the bricks per rank, and the largest single brick's share of the ideal.
"""
import csv
import heapq
import sys


def dynamic_makespan(costs, ranks):
    free = [(0.0, r) for r in range(ranks)]
    heapq.heapify(free)
    for c in costs:
        t, r = heapq.heappop(free)
        heapq.heappush(free, (t + c, r))
    return max(t for t, _ in free)


def static_makespan(costs, ranks):
    load = [0.0] * ranks
    for b, c in enumerate(costs):
        load[b % ranks] += c
    return max(load)


def main():
    rows = list(csv.reader(open(sys.argv[1])))
    by_brick = {}
    for brick, _rank, seconds, *_ in rows:
        by_brick[int(brick)] = float(seconds)
    costs = [by_brick[b] for b in sorted(by_brick)]
    total = sum(costs)
    ranks = [int(r) for r in sys.argv[2:]] or [1, 2, 4, 10, 100, 1000]
    print(f"{len(costs)} bricks, total {total:.3f} s, largest {max(costs):.4f} s, "
          f"mean {total / len(costs):.5f} s, bricks above 10x the mean: "
          f"{sum(c > 10 * total / len(costs) for c in costs)}")
    print("ranks  bricks/rank  dynamic max/ideal  static max/ideal  largest brick/ideal")
    for r in ranks:
        ideal = total / r
        print(f"{r:5d}  {len(costs) / r:11.1f}  {dynamic_makespan(costs, r) / ideal:17.2f}  "
              f"{static_makespan(costs, r) / ideal:16.2f}  {max(costs) / ideal:19.2f}")


if __name__ == "__main__":
    main()
