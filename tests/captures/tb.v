// A testbench standing in for RTL under simulation: it drives a BiSS-C master's MA and a slave's
// SLO (two sensor data frames, CRC6 computed here), a Modbus RTU line (9600 8E1: a request and
// its response) and a T-format line (2.5 Mbaud 8N1: an ID3 request and its response), and dumps
// them as VCD. tests/captures/capture_checks.py runs it with Icarus Verilog and checks what
// `motionbus decode ... capture` finds in the dump.
`timescale 1ns / 1ps
module tb;
  reg ma = 1'b1;
  reg slo = 1'b1;
  reg mb_line = 1'b1;
  reg tf_line = 1'b1;

  // BiSS-C CRC6, x^6 + x + 1, start 0, over the data bits MSB first; sent inverted.
  function [5:0] crc6(input [33:0] d);
    integer i;
    reg [5:0] c;
    reg fb;
    begin
      c = 6'd0;
      for (i = 33; i >= 0; i = i - 1) begin
        fb = c[5] ^ d[i];
        c = {c[4:0], 1'b0};
        if (fb) c = c ^ 6'h03;
      end
      crc6 = ~c;
    end
  endfunction

  // One clock of MA (1 MHz): SLO takes `bit` at the falling edge, MA rises 500 ns later.
  task clock(input bit);
    begin
      ma = 1'b0;
      slo = bit;
      #500 ma = 1'b1;
      #500;
    end
  endtask

  // A sensor data frame as the slave answers it: Ack (3 clocks low), Start, CDS 0, the 32-bit
  // position, nE, nW, the CRC; then SLO back high.
  task biss_frame(input [31:0] position);
    integer i;
    reg [33:0] d;
    reg [5:0] c;
    begin
      d = {position, 1'b1, 1'b1};
      c = crc6(d);
      clock(0); clock(0); clock(0);
      clock(1);
      clock(0);
      for (i = 33; i >= 0; i = i - 1) clock(d[i]);
      for (i = 5; i >= 0; i = i - 1) clock(c[i]);
      slo = 1'b1;
    end
  endtask

  // A UART byte on the Modbus line (which = 1) or the T-format line (which = 0): start bit,
  // 8 data bits LSB first, optional even parity, one stop bit.
  task drive(input which, input level);
    begin
      if (which) mb_line = level;
      else tf_line = level;
    end
  endtask

  task uart(input which, input [7:0] value, input real bit_ns, input even_parity);
    integer i;
    begin
      drive(which, 1'b0);
      #(bit_ns);
      for (i = 0; i < 8; i = i + 1) begin
        drive(which, value[i]);
        #(bit_ns);
      end
      if (even_parity) begin
        drive(which, ^value);
        #(bit_ns);
      end
      drive(which, 1'b1);
      #(bit_ns);
    end
  endtask

  real mb_bit = 104166.667;  // 9600 baud
  real tf_bit = 400.0;       // 2.5 Mbaud
  reg [7:0] mb_request [0:7];
  reg [7:0] mb_response [0:10];
  reg [7:0] tf_response [0:10];
  integer k;

  initial begin
    $dumpfile("capture.vcd");
    $dumpvars(0, tb);
    // Modbus over Serial Line: read 3 holding registers from 107 of slave 17, and the answer
    {mb_request[0], mb_request[1], mb_request[2], mb_request[3], mb_request[4], mb_request[5],
     mb_request[6], mb_request[7]} = 64'h1103006B00037687;
    {mb_response[0], mb_response[1], mb_response[2], mb_response[3], mb_response[4],
     mb_response[5], mb_response[6], mb_response[7], mb_response[8], mb_response[9],
     mb_response[10]} = 88'h110306022B00000064C8BA;
    // T-format: an ID3 response (CF 1A, SF, ABS 3 bytes, ENID, ABM 3 bytes, ALMC, CRC)
    {tf_response[0], tf_response[1], tf_response[2], tf_response[3], tf_response[4],
     tf_response[5], tf_response[6], tf_response[7], tf_response[8], tf_response[9],
     tf_response[10]} = 88'h1A2045230111341200C0AA;
    fork
      begin
        #2000 biss_frame(32'd123456);
        #60000 biss_frame(32'd7);
      end
      begin
        #200000 uart(0, 8'h1A, tf_bit, 0);
        #2000;
        for (k = 0; k < 11; k = k + 1) uart(0, tf_response[k], tf_bit, 0);
      end
      begin
        #1000000;
        for (k = 0; k < 8; k = k + 1) uart(1, mb_request[k], mb_bit, 1);
        #10000000;
        for (k = 0; k < 11; k = k + 1) uart(1, mb_response[k], mb_bit, 1);
      end
    join
    #1000 $finish;
  end
endmodule
