#include "sim/firmware_image.h"

#include <cstdlib>
#include <stdexcept>

extern "C" {
#include <sim_elf.h>
}

namespace sim {

FirmwareImage::FirmwareImage(const std::string& path) : elf_(std::make_unique<elf_firmware_t>()) {
  if (elf_read_firmware(path.c_str(), elf_.get()) != 0)
    throw std::runtime_error("cannot read firmware ELF " + path);
}

FirmwareImage::~FirmwareImage() {
  elf_firmware_t& fw = *elf_;
  std::free(fw.flash);
  std::free(fw.eeprom);
  std::free(fw.fuse);
  std::free(fw.lockbits);
  for (uint32_t i = 0; i < fw.symbolcount; ++i) std::free(fw.symbol[i]);
  std::free(fw.symbol);
}

std::string FirmwareImage::mcu() const { return elf_->mmcu; }

ImageSize FirmwareImage::size() const { return ImageSize{elf_->flashsize, elf_->datasize + elf_->bsssize}; }

void FirmwareImage::default_clock_and_voltages(uint32_t cpu_hz, uint32_t supply_mv) {
  if (!elf_->frequency) elf_->frequency = cpu_hz;
  if (!elf_->vcc) elf_->vcc = supply_mv;
  if (!elf_->avcc) elf_->avcc = supply_mv;
  if (!elf_->aref) elf_->aref = supply_mv;
}

}  // namespace sim
