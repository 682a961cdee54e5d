// A firmware ELF as simavr's loader reads it (RAII over elf_firmware_t, whose buffers
// elf_read_firmware() mallocs), plus the facts the harness reports about the image.
#pragma once

#include <cstdint>
#include <memory>
#include <string>

struct elf_firmware_t;

namespace sim {

// Program and data memory the image uses, as avr-size counts them (text+data, data+bss).
struct ImageSize {
  uint32_t flash_bytes = 0;
  uint32_t ram_bytes = 0;
};

class FirmwareImage {
 public:
  // Throws std::runtime_error if the file cannot be read as an AVR ELF.
  explicit FirmwareImage(const std::string& path);
  ~FirmwareImage();
  FirmwareImage(const FirmwareImage&) = delete;
  FirmwareImage& operator=(const FirmwareImage&) = delete;

  // The MCU named in the image's .mmcu section, "" without one.
  std::string mcu() const;
  ImageSize size() const;
  // Fills clock and voltages the ELF does not carry (simavr's ADC assumes 3.3 V otherwise).
  void default_clock_and_voltages(uint32_t cpu_hz, uint32_t supply_mv);
  elf_firmware_t& elf() { return *elf_; }

 private:
  std::unique_ptr<elf_firmware_t> elf_;
};

}  // namespace sim
