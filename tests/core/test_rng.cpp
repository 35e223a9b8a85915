#include <catch2/catch.hpp>
#include <cmath>

#include "rdsim/core/rng.hpp"

TEST_CASE("rng streams are reproducible and distinct per seed", "[rng]") {
  rdsim::Rng a(42), b(42), c(43);
  bool differs = false;
  for (int i = 0; i < 1000; ++i) {
    auto x = a.next_u64();
    CHECK(x == b.next_u64());
    differs |= x != c.next_u64();
  }
  CHECK(differs);
  auto d1 = rdsim::Rng::derive(42, 1), d2 = rdsim::Rng::derive(42, 2);
  CHECK(d1.next_u64() != d2.next_u64());
}

TEST_CASE("rng uniform and normal have the right moments", "[rng]") {
  rdsim::Rng rng(7);
  const int n = 200000;
  double su = 0, sn = 0, sn2 = 0;
  for (int i = 0; i < n; ++i) {
    double u = rng.uniform();
    REQUIRE(u >= 0.0);
    REQUIRE(u < 1.0);
    su += u;
    double z = rng.normal();
    sn += z;
    sn2 += z * z;
  }
  CHECK(su / n == Approx(0.5).margin(0.005));
  CHECK(sn / n == Approx(0.0).margin(0.01));
  CHECK(sn2 / n == Approx(1.0).margin(0.01));
  for (int i = 0; i < 1000; ++i) CHECK(rng.below(6) < 6);
}
