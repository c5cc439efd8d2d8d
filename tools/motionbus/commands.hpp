// The CLI's commands. Each returns the exit status or throws cli::usage_error.
#ifndef MOTIONBUS_TOOLS_COMMANDS_HPP
#define MOTIONBUS_TOOLS_COMMANDS_HPP

#include <string>
#include <vector>

int command_crc(const std::vector<std::string>& args);
int command_decode(const std::vector<std::string>& args);
int command_encode(const std::vector<std::string>& args);
int command_serve(const std::vector<std::string>& args);
int command_read(const std::vector<std::string>& args);

#endif
