# `corridorsim where ROOM --run DIR` on a hand-written run folder (tests/data/where/run): the room
# per pipeline with its 1-sigma, and exit 2 with one message for a missing or malformed folder or
# map, or an unknown room (naming the known ones).
include("${CMAKE_CURRENT_LIST_DIR}/cli_support.cmake")

set(run "${SOURCE_DIR}/tests/data/where/run")
cli_run(EXIT 0 WHAT "room in both maps" ARGS where 101 --run "${run}"
        STDOUT "^p1_ekf: room 101 at x 12\\.500 m \\(1-sigma 0\\.100 m\\), y -1\\.150 m \\(1-sigma 0\\.200 m\\), landmark 4\np1_vision: room 101 at x 12\\.750 m \\(1-sigma 0\\.250 m\\), y -1\\.250 m \\(1-sigma 0\\.300 m\\), landmark 2\n$")
cli_run(EXIT 0 WHAT "room in one map" ARGS where 102 --run "${run}"
        STDOUT "^p1_ekf: room 102 at x 20\\.250 m \\(1-sigma 0\\.150 m\\), y 1\\.150 m \\(1-sigma 0\\.030 m\\), landmark 9\np1_vision: room 102 is not in its map\n$")
cli_run(EXIT 0 WHAT "one pipeline" ARGS where 101 --run "${run}" --pipeline p1_vision
        STDOUT "^p1_vision: room 101 at x 12\\.750 m")
cli_run(EXIT 2 WHAT "unknown room"  ARGS where 999 --run "${run}"
        STDERR "^corridorsim: error: command line: ROOM: room '999' is not in any of the run's semantic maps \\(known rooms: 101, 102\\)\n$")
cli_run(EXIT 2 WHAT "unknown room in one map" ARGS where 102 --run "${run}" --pipeline p1_vision
        STDERR "ROOM: room '102' is not in the p1_vision map \\(known rooms: 101\\)")
cli_run(EXIT 2 WHAT "unknown pipeline" ARGS where 101 --run "${run}" --pipeline nope
        STDERR "maps/nope_semantic\\.json: does not exist \\(pipelines with a semantic map: p1_ekf, p1_vision\\)")
cli_run(EXIT 2 WHAT "no run folder" ARGS where 101 --run "${WORK_DIR}/none"
        STDERR "command line: --run: no such folder")
file(MAKE_DIRECTORY "${WORK_DIR}/no_maps")
cli_run(EXIT 2 WHAT "no maps folder" ARGS where 101 --run "${WORK_DIR}/no_maps"
        STDERR "no_maps/maps: no such folder: the run wrote no maps")
file(MAKE_DIRECTORY "${WORK_DIR}/empty/maps")
file(WRITE "${WORK_DIR}/empty/maps/p1_ekf.bt" "")
cli_run(EXIT 2 WHAT "no semantic map" ARGS where 101 --run "${WORK_DIR}/empty"
        STDERR "empty/maps: no <pipeline>_semantic\\.json: no pipeline of this run wrote")
file(MAKE_DIRECTORY "${WORK_DIR}/bad/maps")
file(WRITE "${WORK_DIR}/bad/maps/a_semantic.json" "{\n  \"format\": \"corridorsim.semantic_map\",\n  oops\n")
cli_run(EXIT 2 WHAT "malformed JSON" ARGS where 101 --run "${WORK_DIR}/bad"
        STDERR "bad/maps/a_semantic\\.json:3:3: not JSON: ")
file(WRITE "${WORK_DIR}/bad/maps/a_semantic.json"
     "{\"format\": \"corridorsim.semantic_map\", \"version\": 1, \"frame\": \"world\", \"rooms\": [{\"room\": \"101\", \"landmark_id\": 1, \"position_m\": [1, 2], \"covariance_m2\": [[1, 0], [0, 1]]}]}")
cli_run(EXIT 2 WHAT "malformed key" ARGS where 101 --run "${WORK_DIR}/bad"
        STDERR "bad/maps/a_semantic\\.json: rooms\\[0\\]\\.position_m: expected \\[x, y, z\\] in metres\n$")
file(REMOVE "${WORK_DIR}/bad/maps/a_semantic.json")
file(MAKE_DIRECTORY "${WORK_DIR}/bad/maps/a_semantic.json")
cli_run(EXIT 2 WHAT "a folder for a map" ARGS where 101 --run "${WORK_DIR}/bad"
        STDERR "a_semantic\\.json: not a regular file")
cli_run(EXIT 2 WHAT "bad room" ARGS where "1 01" --run "${run}"
        STDERR "command line: ROOM: expected a room number")
cli_run(EXIT 2 WHAT "bad pipeline" ARGS where 101 --run "${run}" --pipeline "../x"
        STDERR "command line: --pipeline: expected a pipeline name")
cli_run(EXIT 2 WHAT "no --run" ARGS where 101 STDERR "command line: .*--run")
cli_run(EXIT 0 WHAT "help" ARGS where --help STDOUT "Exit codes: 0 success, 2 bad input")
# Nesting is bounded before the map is parsed (16 MiB of `[` took gigabytes), at its line.
file(REMOVE_RECURSE "${WORK_DIR}/bad/maps/a_semantic.json")
string(REPEAT "[" 100000 deep)
file(WRITE "${WORK_DIR}/bad/maps/a_semantic.json" "{\"rooms\":\n${deep}")
cli_run(EXIT 2 WHAT "deep nesting" ARGS where 101 --run "${WORK_DIR}/bad"
        STDERR "bad/maps/a_semantic\\.json:2:64: more than 64 nested arrays and objects\n$")
