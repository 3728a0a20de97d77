#pragma once
namespace tandem::bench {
/// Registers the Google Benchmark micro-benchmarks (Micro.cpp) with the library.
void registerMicroBenchmarks();
}  // namespace tandem::bench
