#pragma once
// What a DAE (COLLADA) file must satisfy before Assimp reads it: the checks that keep Assimp 5.2's
// COLLADA parser from running out of memory or reading outside its arrays (both found by fuzz_mesh).
#include <string>

namespace rdsim {

// Throws rdsim::Error "<file>: not a readable DAE file: <why>" unless, in `xml` (the file's bytes):
//  - the integer lists (<p>, <v>, <vcount>, <h>) hold only digits, signs and spaces, and the
//    <float_array> lists only what numbers are made of: Assimp reads an integer list until its text
//    ends and never consumes a stray byte, growing the list until memory runs out;
//  - no count attribute exceeds what max_mesh_triangles allows: `count` sizes a list before any of
//    it is read;
//  - every <accessor> reads inside the array it names: Assimp checks an index against the accessor's
//    count but reads the array at offset + index * stride without checking the array's length (an
//    array without a count holds nothing, so any read of it went through a null pointer).
void check_dae_file(const std::string& xml, const std::string& file);

}  // namespace rdsim
