#include "machine/unit_module.h"

#include <algorithm>
#include <string>

namespace rtm {
namespace {
bool any_of(const std::vector<UnitKind>& of, std::initializer_list<UnitKind> kinds) {
  return std::any_of(kinds.begin(), kinds.end(),
                     [&](UnitKind k) { return std::find(of.begin(), of.end(), k) != of.end(); });
}
}  // namespace

UnitModule::UnitModule(sc_core::sc_module_name name, PeContext& ctx,
                       std::initializer_list<UnitKind> kinds)
    : sc_module(name), ctx_(ctx) {
  for (const FifoSpec& f : fifo_table()) {
    if (f.per_lane) continue;  // inside an intersection unit
    const bool reads = any_of(f.readers, kinds), writes = any_of(f.writers, kinds);
    const std::string in = std::string(f.name) + "_in", out = std::string(f.name) + "_out";
    if (f.payload == Payload::Ray) {
      if (reads) rays_in_[size_t(f.id)] = std::make_unique<In<MachineRay>>(in.c_str());
      if (writes) rays_out_[size_t(f.id)] = std::make_unique<Out<MachineRay>>(out.c_str());
    } else if (f.payload == Payload::End) {
      if (reads) ends_in_ = std::make_unique<In<RayEnd>>(in.c_str());
      if (writes) ends_out_ = std::make_unique<Out<RayEnd>>(out.c_str());
    }
  }
}

void UnitModule::bind(FifoId id, MeteredFifo<MachineRay>& f) {
  if (rays_in_[size_t(id)]) rays_in_[size_t(id)]->bind(f);
  if (rays_out_[size_t(id)]) rays_out_[size_t(id)]->bind(f);
}

void UnitModule::bind(FifoId, MeteredFifo<RayEnd>& f) {
  if (ends_in_) ends_in_->bind(f);
  if (ends_out_) ends_out_->bind(f);
}

bool UnitModule::try_write(const Output& o, const MachineRay& r, UnitKind kind, int index) {
  if (o.what == Output::What::End) {
    if ((*ends_out_)->num_free() == 0) return false;
    (*ends_out_)->write(RayEnd{r.id});
  } else {
    Out<MachineRay>& out = *rays_out_[size_t(o.fifo)];
    if (out->num_free() == 0) return false;
    out->write(r);
  }
  record_put(ctx_, ctx_.put_time(), kind, index, r, o);
  return true;
}

Dispatcher::Dispatcher(sc_core::sc_module_name name, MeteredFifo<MachineRay>& in, int units)
    : sc_module(name), in_(in), waiting_(0) {
  for (int i = 0; i < units; ++i) wake_.push_back(std::make_unique<sc_core::sc_event>());
  SC_METHOD(dispatch);
  sensitive << in_.data_written_event();
  dont_initialize();
}

void Dispatcher::dispatch() {
  // Immediate notifications: the units run next, in the order notified, and each takes one ray.
  for (int n = in_.num_available(); n > 0 && waiting_.any_idle(); --n)
    wake_[size_t(waiting_.take())]->notify();
}

}  // namespace rtm
