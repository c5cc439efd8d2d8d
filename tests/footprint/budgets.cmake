# Footprint budgets: probe, target -> .text bytes, .rodata bytes (see docs/footprint.md).
# Set at the sizes measured on 2026-11-22 (session 4) plus about 10 %, rounded up to 16 bytes,
# and never above the project's Cortex-M4 targets (T-format master 600 B, BiSS-C frame decoder
# 400 B, Modbus client 2048 B, Modbus server with dispatch 2560 B of .text), so that the test
# command also checks those. A probe that grows past its budget fails the test run; lower a
# budget when the code shrinks.
set(footprint_budget_biss_decoder_cortex-m0plus 448 288)
set(footprint_budget_biss_decoder_cortex-m4 400 288)  # the project target
set(footprint_budget_biss_decoder_rv32imc 2432 320)
set(footprint_budget_biss_master_cortex-m0plus 1120 576)
set(footprint_budget_biss_master_cortex-m4 1040 576)
set(footprint_budget_biss_master_rv32imc 3568 640)
set(footprint_budget_biss_slave_cortex-m0plus 2544 656)
set(footprint_budget_biss_slave_cortex-m4 2592 656)
set(footprint_budget_biss_slave_rv32imc 4032 640)
set(footprint_budget_modbus_client_cortex-m0plus 656 576)
set(footprint_budget_modbus_client_cortex-m4 720 576)
set(footprint_budget_modbus_client_rv32imc 2224 576)
set(footprint_budget_modbus_server_cortex-m0plus 2720 576)
set(footprint_budget_modbus_server_cortex-m4 2560 576)  # the project target
set(footprint_budget_modbus_server_rv32imc 3376 656)
set(footprint_budget_tformat_encoder_cortex-m0plus 944 80)
set(footprint_budget_tformat_encoder_cortex-m4 944 80)
set(footprint_budget_tformat_encoder_rv32imc 1312 464)
set(footprint_budget_tformat_master_cortex-m0plus 736 80)
set(footprint_budget_tformat_master_cortex-m4 600 80)  # the project target
set(footprint_budget_tformat_master_rv32imc 1072 80)
set(footprint_budget_modbus_server_core_cortex-m0plus 1744 16)
set(footprint_budget_modbus_server_core_cortex-m4 1700 16)  # the project target
set(footprint_budget_modbus_server_core_rv32imc 2384 16)
