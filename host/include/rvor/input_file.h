#pragma once
// Opening a file the user named for reading, with one message for every reader: what the file is
// for, its path, and why it cannot be read (missing, unreadable, a directory).
#include <fstream>
#include <string>

namespace rvor {

// `what` names the file's role, e.g. "mesh file" or "point file". Throws rvor::Error
// "cannot read WHAT PATH: REASON".
std::ifstream open_input_file(const std::string& path, const std::string& what);

}  // namespace rvor
