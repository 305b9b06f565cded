#include <iostream>

#include <navaid/core/geometry.hpp>
#include <navaid/core/time.hpp>

int main() {
  const navaid::SE3 T = navaid::se3_exp((navaid::Vec6() << 1, 2, 3, 0.1, 0.2, 0.3).finished());
  const navaid::Vec6 xi = navaid::se3_log(T);
  std::cout << navaid::format_seconds(navaid::seconds_to_ns(1.5)) << " " << xi.transpose() << "\n";
  return (xi - (navaid::Vec6() << 1, 2, 3, 0.1, 0.2, 0.3).finished()).norm() < 1e-9 ? 0 : 1;
}
