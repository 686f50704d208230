#pragma once
// The one exception type svr throws at its boundaries (parsing, unknown names, bad parameters,
// renders that fail). Messages name the file, the key and the offending value so that a user
// can fix the input. Part of the public API (include/svr/svr.h).

#include <stdexcept>
#include <string>

namespace svr {

class Error : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

// A render stopped on request before it finished (the Python module's Ctrl-C): no image.
class Cancelled : public Error {
 public:
  using Error::Error;
};

}  // namespace svr
