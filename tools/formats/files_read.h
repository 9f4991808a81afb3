// The files this process's readers opened: the input, and the files it names
// or has beside it (a TetGen .ele and .face, an Abaqus *INCLUDE, a NRRD's
// data file, a .pvtu's pieces). meshenc refuses an output that is one of
// them: writing it would destroy what was just read.
#pragma once

#include <string>
#include <vector>

namespace dtm {

void note_file_read(const std::string& path);
std::vector<std::string> files_read();

}  // namespace dtm
