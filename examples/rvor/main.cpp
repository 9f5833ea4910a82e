#include <iostream>

int main() {
  std::cout << "rvor: under construction\n";
  return 0;
}
