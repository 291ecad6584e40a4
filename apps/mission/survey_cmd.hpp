// tiller-mission's `survey` subcommand (survey_cmd.cpp): argv[1] is "survey".
#pragma once

int survey_main(int argc, char** argv);
