#pragma once
// The one exception type thrown at boundaries (parsing, unknown names, bad parameters).
// Messages name the file, the key and the offending value so a user can fix the input.

#include <stdexcept>
#include <string>

namespace svr {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

}  // namespace svr
