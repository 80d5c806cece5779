// The programs' version: the project's version and, in a git checkout, `git describe` at build time.
#pragma once

namespace emboss {

// "0.1.0 (git 706e2f4-dirty)", or "0.1.0" when built outside git. Written into version.cpp in the
// build folder at every build, which changes only when the description does.
const char* versionString();

}  // namespace emboss
