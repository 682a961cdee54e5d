# The boards one configure builds: name, MCU, header namespace, avrdude programmer and baud.
# Data only; firmware/CMakeLists.txt and the flash targets read it.
set(HOTEND_BOARDS sanguinololu ramps14)
set(HOTEND_BOARD_sanguinololu_MCU atmega1284p)
set(HOTEND_BOARD_sanguinololu_AVRDUDE_PART m1284p)
set(HOTEND_BOARD_sanguinololu_PROGRAMMER arduino)   # optiboot/stk500v1 bootloader
set(HOTEND_BOARD_sanguinololu_BAUD 115200)
set(HOTEND_BOARD_ramps14_MCU atmega2560)
set(HOTEND_BOARD_ramps14_AVRDUDE_PART m2560)
set(HOTEND_BOARD_ramps14_PROGRAMMER wiring)         # Mega2560 stk500v2 bootloader
set(HOTEND_BOARD_ramps14_BAUD 115200)
