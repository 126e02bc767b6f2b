// The results folder of a run or a sample build, made before anything is computed: a folder that
// cannot hold results is bad input, said in one line, not an error after the work is done.
#pragma once

#include <initializer_list>
#include <string>

namespace trackbed {

// Creates `folder` and its `subfolders` and checks that a file can be written there; InputError
// "<where>: ... cannot ...; valid: ..." otherwise (a file in its place, a folder under /proc, a
// read-only file system, no permission). `where` names the file and parameter that gave it.
void create_output_folders(const std::string& folder, std::initializer_list<const char*> subfolders,
                           const std::string& where);

// The `where` of a results folder given by `output/folder` in the parameter file `file`:
// "<file>: output/folder = <folder>" (a long name shortened).
std::string output_folder_parameter(const std::string& file, const std::string& folder);

}  // namespace trackbed
