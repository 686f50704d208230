#pragma once
// Output files appear whole or not at all (issue 9): every writer writes a temporary sibling
// (same folder, so the rename cannot cross file systems) and renames it over the target. An
// interrupted or failed write leaves the previous file, if any, and no partial one; the
// temporary is removed when the write throws.

#include <functional>
#include <string>

namespace svr {

// Calls write(tmp) with the temporary's path, then renames it to `path`. Throws svr::Error
// naming `path` when the rename fails; rethrows what `write` throws.
void writeFileAtomically(const std::string& path, const std::function<void(const std::string&)>& write);

// `text` as the whole content of `path`.
void writeTextAtomically(const std::string& path, const std::string& text);

}  // namespace svr
