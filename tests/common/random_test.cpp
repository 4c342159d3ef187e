#include "common/random.h"

#include <cmath>
#include <vector>

#include <catch2/catch.hpp>

namespace corridorsim {
namespace {

// Golden values: if one of these changes, every seeded output of the project changes. Update
// them only on purpose, and say so in the change.
TEST_CASE("random streams reproduce their golden values", "[random]") {
  RandomStream raw(42, 0, "test.stream");
  CHECK(raw.NextU64() == 0x6a2f53f5f13b8e90ULL);
  CHECK(raw.NextU64() == 0xa2f0d0a5d3435fcfULL);
  CHECK(raw.NextU64() == 0xea0327ca4cc35f12ULL);

  RandomStream uniform(42, 0, "test.uniform");
  CHECK(uniform.Uniform01() == 0.96137935164814603);
  CHECK(uniform.Uniform01() == 0.43036008162169492);
  CHECK(uniform.Uniform01() == 0.47767319837611988);

  RandomStream normal(42, 0, "test.normal");
  CHECK(normal.Normal() == 0.97198916707737637);
  CHECK(normal.Normal() == -1.0214016234685177);
  CHECK(normal.Normal() == 1.9890677134125905);
  CHECK(normal.Normal() == 0.24087575322470786);

  RandomStream ints(42, 0, "test.int");
  const std::vector<std::int64_t> expected = {-1, 3, 4, 1, 2};
  for (const auto e : expected) CHECK(ints.UniformInt(-3, 7) == e);

  CHECK(HashName("worlds.doors") == 0x01c3846def70bd0fULL);
}

TEST_CASE("a stream is determined by seed, run index and component name", "[random]") {
  RandomStream a(7, 3, "sim.odometry"), b(7, 3, "sim.odometry");
  for (int i = 0; i < 100; ++i) REQUIRE(a.NextU64() == b.NextU64());

  RandomStream other_seed(8, 3, "sim.odometry"), other_run(7, 4, "sim.odometry"),
      other_name(7, 3, "sim.camera");
  RandomStream ref(7, 3, "sim.odometry");
  const auto first = ref.NextU64();
  CHECK(other_seed.NextU64() != first);
  CHECK(other_run.NextU64() != first);
  CHECK(other_name.NextU64() != first);
}

TEST_CASE("derived streams depend on identity, not on how far the parent has drawn", "[random]") {
  RandomStream parent(1, 0, "render");
  RandomStream child_before = parent.Derive("front");
  for (int i = 0; i < 10; ++i) parent.NextU64();
  RandomStream child_after = parent.Derive("front");
  CHECK(child_before.NextU64() == child_after.NextU64());
  CHECK(parent.Derive("front").NextU64() != parent.Derive("upward").NextU64());
}

TEST_CASE("uniform draws stay in range and have the right mean and variance", "[random]") {
  RandomStream r(5, 0, "test.moments");
  const int n = 200000;
  double sum = 0, sum2 = 0;
  for (int i = 0; i < n; ++i) {
    const double u = r.Uniform(2.0, 5.0);
    REQUIRE(u >= 2.0);
    REQUIRE(u < 5.0);
    sum += u;
    sum2 += u * u;
  }
  const double mean = sum / n, var = sum2 / n - mean * mean;
  CHECK(mean == Approx(3.5).margin(0.01));
  CHECK(var == Approx(0.75).epsilon(0.02));  // (b - a)^2 / 12
}

TEST_CASE("normal draws have the requested mean and standard deviation", "[random]") {
  RandomStream r(5, 0, "test.normal_moments");
  const int n = 200000;
  double sum = 0, sum2 = 0, sum4 = 0;
  for (int i = 0; i < n; ++i) {
    const double x = r.Normal(1.5, 2.0);
    sum += x;
    sum2 += (x - 1.5) * (x - 1.5);
    sum4 += std::pow((x - 1.5) / 2.0, 4);
  }
  CHECK(sum / n == Approx(1.5).margin(0.02));
  CHECK(std::sqrt(sum2 / n) == Approx(2.0).epsilon(0.01));
  CHECK(sum4 / n == Approx(3.0).epsilon(0.05));  // kurtosis of a Gaussian
}

TEST_CASE("ziggurat normal draws follow the standard normal distribution, tails included",
          "[random]") {
  RandomStream r(6, 0, "test.ziggurat");
  const int n = 2000000;
  double sum = 0, sum2 = 0, sum4 = 0;
  // Bins of the CDF at -3, -2, -1, -0.5, 0, 0.5, 1, 2, 3 and the tails beyond +-3.65 (the
  // ziggurat's base layer: values there come from the separate tail sampler).
  const std::vector<double> edges = {-3, -2, -1, -0.5, 0, 0.5, 1, 2, 3};
  std::vector<int> below(edges.size(), 0);
  int tail = 0;
  for (int i = 0; i < n; ++i) {
    const double x = r.StandardNormalZiggurat();
    sum += x;
    sum2 += x * x;
    sum4 += x * x * x * x;
    for (std::size_t k = 0; k < edges.size(); ++k) below[k] += x < edges[k];
    tail += std::abs(x) > 3.6541528853610088;
  }
  CHECK(sum / n == Approx(0.0).margin(0.003));
  CHECK(sum2 / n == Approx(1.0).epsilon(0.003));
  CHECK(sum4 / n == Approx(3.0).epsilon(0.01));
  for (std::size_t k = 0; k < edges.size(); ++k) {
    const double p = 0.5 * std::erfc(-edges[k] / std::sqrt(2.0));
    // Within 4 binomial standard deviations of the normal CDF.
    CHECK(below[k] / double(n) == Approx(p).margin(4 * std::sqrt(p * (1 - p) / n)));
  }
  const double p_tail = std::erfc(3.6541528853610088 / std::sqrt(2.0));  // ~2.6e-4
  CHECK(tail / double(n) == Approx(p_tail).margin(4 * std::sqrt(p_tail / n)));
}

TEST_CASE("ziggurat normal draws are reproducible from the seed", "[random]") {
  RandomStream a(8, 1, "test.ziggurat_repeat"), b(8, 1, "test.ziggurat_repeat");
  for (int i = 0; i < 1000; ++i) REQUIRE(a.StandardNormalZiggurat() == b.StandardNormalZiggurat());
}

TEST_CASE("uniform integers cover their inclusive range evenly", "[random]") {
  RandomStream r(9, 0, "test.ints");
  std::vector<int> counts(6, 0);
  const int n = 60000;
  for (int i = 0; i < n; ++i) {
    const auto k = r.UniformInt(10, 15);
    REQUIRE(k >= 10);
    REQUIRE(k <= 15);
    ++counts[static_cast<std::size_t>(k - 10)];
  }
  for (const int c : counts) CHECK(c == Approx(n / 6.0).epsilon(0.05));
}

TEST_CASE("categorical draws follow their weights and never pick a zero weight", "[random]") {
  RandomStream r(11, 0, "test.categorical");
  const std::vector<double> weights = {0.5, 0.0, 0.3, 0.2};
  std::vector<int> counts(4, 0);
  const int n = 50000;
  for (int i = 0; i < n; ++i) ++counts[r.Categorical(weights)];
  CHECK(counts[1] == 0);
  CHECK(counts[0] / double(n) == Approx(0.5).margin(0.01));
  CHECK(counts[2] / double(n) == Approx(0.3).margin(0.01));
  CHECK(counts[3] / double(n) == Approx(0.2).margin(0.01));
}

TEST_CASE("exponential and Bernoulli draws match their means", "[random]") {
  RandomStream r(13, 0, "test.exp");
  const int n = 100000;
  double sum = 0;
  int hits = 0;
  for (int i = 0; i < n; ++i) {
    sum += r.Exponential(4.0);
    hits += r.Bernoulli(0.25);
  }
  CHECK(sum / n == Approx(0.25).epsilon(0.02));
  CHECK(hits / double(n) == Approx(0.25).margin(0.005));
}

TEST_CASE("shuffle is a seeded permutation", "[random]") {
  std::vector<int> a(20), b(20);
  for (int i = 0; i < 20; ++i) a[i] = b[i] = i;
  RandomStream r1(3, 0, "test.shuffle"), r2(3, 0, "test.shuffle");
  r1.Shuffle(a);
  r2.Shuffle(b);
  CHECK(a == b);
  std::vector<int> sorted = a;
  std::sort(sorted.begin(), sorted.end());
  for (int i = 0; i < 20; ++i) CHECK(sorted[i] == i);
  bool moved = false;
  for (int i = 0; i < 20; ++i) moved |= a[i] != i;
  CHECK(moved);
}

// Poisson: golden values on both sides of the switch between the multiplication method (mean < 10)
// and PTRS (mean >= 10); update them only on purpose, as above.
TEST_CASE("Poisson draws reproduce their golden values", "[random]") {
  RandomStream r(42, 0, "test.poisson");
  const std::vector<std::int64_t> expected = {0,  0,  1,  0,  1,    1,   9,      8,
                                              10, 16, 40, 41, 1028, 971, 123403, 123946};
  std::vector<std::int64_t> got;
  for (const double mean : {0.0, 0.5, 3.0, 9.99, 10.0, 42.0, 1000.0, 123456.0}) {
    got.push_back(r.Poisson(mean));
    got.push_back(r.Poisson(mean));
  }
  CHECK(got == expected);
}

TEST_CASE("Poisson draws have mean and variance equal to their mean", "[random]") {
  for (const double mean : {0.3, 2.5, 9.9, 10.0, 17.0, 150.0, 5000.0}) {
    RandomStream r(17, 0, "test.poisson_moments");
    const int n = 200000;
    double sum = 0, sum2 = 0;
    for (int i = 0; i < n; ++i) {
      const auto k = r.Poisson(mean);
      REQUIRE(k >= 0);
      sum += static_cast<double>(k);
      sum2 += static_cast<double>(k) * static_cast<double>(k);
    }
    const double m = sum / n, var = sum2 / n - m * m;
    CAPTURE(mean);
    CHECK(m == Approx(mean).margin(5 * std::sqrt(mean / n)));  // 5 standard errors
    CHECK(var == Approx(mean).epsilon(0.02));
  }
}

TEST_CASE("Poisson draws follow the probability mass function", "[random]") {
  // Both methods: every k with P(k) > 0.5 % is drawn with its probability within 5 standard errors.
  for (const double mean : {4.0, 12.0, 30.0}) {
    RandomStream r(19, 0, "test.poisson_pmf");
    const int n = 200000;
    std::vector<int> counts(200, 0);
    for (int i = 0; i < n; ++i) {
      const auto k = r.Poisson(mean);
      if (k < 200) ++counts[static_cast<std::size_t>(k)];
    }
    double log_p = -mean;  // log P(0)
    for (int k = 0; k < 200; ++k) {
      if (k > 0) log_p += std::log(mean / k);
      const double p = std::exp(log_p);
      if (p < 0.005) continue;
      CAPTURE(mean, k);
      CHECK(counts[static_cast<std::size_t>(k)] / double(n) ==
            Approx(p).margin(5 * std::sqrt(p * (1 - p) / n)));
    }
  }
}

}  // namespace
}  // namespace corridorsim
