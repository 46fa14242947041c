#pragma once

#include <cstddef>
#include <filesystem>
#include <map>
#include <optional>
#include <string>
#include <vector>

namespace granular {

/// Labels in file names. Real labels are free text (PandaSet's "Medium-sized_Truck",
/// "Tram_/_Subway", spaces, non-ASCII), but a file name must split back into label, stamp and
/// index, must not hide itself behind a leading '.', and cannot hold a '/'. So every byte of the
/// label outside [A-Za-z0-9_.], and a leading '.', is written as '%' and two upper-case hex
/// digits: "Medium-sized_Truck" is "Medium%2Dsized_Truck", "Tram_/_Subway" "Tram_%2F_Subway".
/// Plain labels (Sedan, SchoolBus) are unchanged, so names keep the report's form. The rule is
/// granular_tools/labels.py's too, checked against the same cases (test/data/label_names.tsv).
std::string encodeLabel(const std::string& label);

/// The label of an encoded one; nullopt when `encoded` is not one encodeLabel could give.
std::optional<std::string> decodeLabel(const std::string& encoded);

/// The most bytes an encoded label may take, so that every name stays within the 255 bytes a
/// file name may have.
constexpr std::size_t kMaxEncodedLabel = 200;

/// `<label>-<stamp>-<label_index>.pcd`, the label encoded (encodeLabel). Throws
/// std::invalid_argument naming the label when it is empty or too long once encoded.
std::string objectFileName(const std::string& label, const std::string& stamp,
                           std::size_t label_index);

/// The label of an object file (`<label>-<stamp>-<index>.pcd`), decoded; empty when the name
/// has no label part or one that encodeLabel could not have given.
std::string objectClass(const std::filesystem::path& file);

/// `<label>.pcd` for a class model (encodeLabel); the same errors as objectFileName.
std::string modelFileName(const std::string& label);

/// The label of a class model file, decoded; empty when the name could not be modelFileName's.
std::string modelClass(const std::filesystem::path& file);

/// Throws std::runtime_error "<folder>: no such objects folder" when `folder` is not a folder.
void requireObjectsFolder(const std::filesystem::path& folder);

/// The object PCDs of an objects folder by class, each list sorted by file name. Hidden files
/// and other extensions are ignored; a PCD whose name has no class goes to `unnamed`, when
/// given. Throws std::runtime_error when `folder` is not a folder.
std::map<std::string, std::vector<std::filesystem::path>> listObjectFiles(
    const std::filesystem::path& folder, std::vector<std::string>* unnamed = nullptr);

/// Every object PCD of an objects folder, those without a class in their name included, in
/// name order; `by_class`, when given, receives them by class as listObjectFiles gives them.
/// Throws std::runtime_error naming the folder when it is not a folder or holds no object PCD.
std::vector<std::filesystem::path> listAllObjectFiles(
    const std::filesystem::path& folder,
    std::map<std::string, std::vector<std::filesystem::path>>* by_class = nullptr);

}  // namespace granular
