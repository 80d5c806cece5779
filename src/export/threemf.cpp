// 3MF through lib3mf's C interface.
#include "export/threemf.h"

#include <Model/COM/NMR_DLLInterfaces.h>

#include <vector>

namespace emboss {

namespace {

// Releases a lib3mf object when it goes out of scope.
struct Held {
  NMR::PLib3MFBase* p = nullptr;
  Held() = default;
  Held(const Held&) = delete;
  Held& operator=(const Held&) = delete;
  ~Held() {
    if (p) NMR::lib3mf_release(p);
  }
};

std::string lastError(NMR::PLib3MFBase* object, const char* what) {
  DWORD code = 0;
  LPCSTR message = nullptr;
  if (object) NMR::lib3mf_getlasterror(object, &code, &message);
  std::string s = std::string("lib3mf: ") + what;
  if (message && *message) s += std::string(": ") + message;
  if (code) s += " (error " + std::to_string(code) + ")";
  return s;
}

}  // namespace

Status write3mf(const TriangleMesh& mesh, const ThreeMfInfo& info, const std::string& path) {
  Held model, object, item, writer;
  if (NMR::lib3mf_createmodel(&model.p) != LIB3MF_OK) return fail(lastError(nullptr, "cannot create a model"));
  if (NMR::lib3mf_model_setunit(model.p, NMR::MODELUNIT_MILLIMETER) != LIB3MF_OK) return fail(lastError(model.p, "unit"));
  if (!info.title.empty() && NMR::lib3mf_model_addmetadatautf8(model.p, "Title", info.title.c_str()) != LIB3MF_OK)
    return fail(lastError(model.p, "title"));
  if (!info.description.empty() &&
      NMR::lib3mf_model_addmetadatautf8(model.p, "Description", info.description.c_str()) != LIB3MF_OK)
    return fail(lastError(model.p, "description"));
  if (NMR::lib3mf_model_addmeshobject(model.p, &object.p) != LIB3MF_OK) return fail(lastError(model.p, "mesh object"));
  NMR::lib3mf_object_setnameutf8(object.p, info.title.empty() ? "emboss piece" : info.title.c_str());
  std::vector<NMR::MODELMESHVERTEX> vertices(mesh.vertices.size());
  for (size_t v = 0; v < mesh.vertices.size(); ++v)
    for (int a = 0; a < 3; ++a) vertices[v].m_fPosition[a] = mesh.vertices[v][a];
  std::vector<NMR::MODELMESHTRIANGLE> triangles(mesh.triangles.size());
  for (size_t t = 0; t < mesh.triangles.size(); ++t)
    for (int a = 0; a < 3; ++a) triangles[t].m_nIndices[a] = mesh.triangles[t][a];
  if (NMR::lib3mf_meshobject_setgeometry(object.p, vertices.data(), static_cast<DWORD>(vertices.size()),
                                         triangles.data(), static_cast<DWORD>(triangles.size())) != LIB3MF_OK)
    return fail(lastError(object.p, "geometry"));
  if (NMR::lib3mf_model_addbuilditem(model.p, object.p, nullptr, &item.p) != LIB3MF_OK)
    return fail(lastError(model.p, "build item"));
  if (NMR::lib3mf_model_querywriter(model.p, "3mf", &writer.p) != LIB3MF_OK) return fail(lastError(model.p, "writer"));
  if (NMR::lib3mf_writer_writetofileutf8(writer.p, path.c_str()) != LIB3MF_OK)
    return fail(lastError(writer.p, ("cannot write " + path).c_str()));
  return Ok{};
}

Result<ThreeMfSummary> read3mfSummary(const std::string& path) {
  Held model, reader, iterator, resource;
  if (NMR::lib3mf_createmodel(&model.p) != LIB3MF_OK) return fail(lastError(nullptr, "cannot create a model"));
  if (NMR::lib3mf_model_queryreader(model.p, "3mf", &reader.p) != LIB3MF_OK) return fail(lastError(model.p, "reader"));
  if (NMR::lib3mf_reader_readfromfileutf8(reader.p, path.c_str()) != LIB3MF_OK)
    return fail(lastError(reader.p, ("cannot read " + path).c_str()));
  ThreeMfSummary s;
  DWORD unit = 0;
  NMR::lib3mf_model_getunit(model.p, &unit);
  s.unit = unit == NMR::MODELUNIT_MILLIMETER ? "millimeter" : std::to_string(unit);
  if (NMR::lib3mf_model_getmeshobjects(model.p, &iterator.p) != LIB3MF_OK) return fail(lastError(model.p, "objects"));
  BOOL has = false;
  if (NMR::lib3mf_resourceiterator_movenext(iterator.p, &has) != LIB3MF_OK || !has) return fail(path + ": no mesh object");
  if (NMR::lib3mf_resourceiterator_getcurrent(iterator.p, &resource.p) != LIB3MF_OK) return fail(lastError(iterator.p, "object"));
  DWORD n = 0;
  NMR::lib3mf_meshobject_gettrianglecount(resource.p, &n);
  s.triangles = n;
  NMR::lib3mf_meshobject_getvertexcount(resource.p, &n);
  s.vertices = n;
  BOOL ok = false;
  NMR::lib3mf_meshobject_ismanifoldandoriented(resource.p, &ok);
  s.manifoldAndOriented = ok;
  return s;
}

}  // namespace emboss
