#!/usr/bin/env bash
# A syntax check of a udev rules file, for Debian 12 whose udevadm has no `verify` (udev 252):
# every rule line is comma-separated KEY[{attr}]OP"value" items; a key udev only matches on
# takes == or !=, a key it only assigns takes =, +=, -= or :=, an unknown key is an error.
# Then each VID:PID given after the file (the ones protocol/README.md names) must have a rule.
# Usage: check_udev_rule.sh RULES VID:PID...   Prints one line per fault; exit 1 on any.
set -uo pipefail
rules=$1
shift
match_only=" ACTION DEVPATH KERNEL KERNELS SUBSYSTEM SUBSYSTEMS DRIVER DRIVERS ATTRS TAGS TEST PROGRAM RESULT CONST "
assign_only=" OWNER GROUP MODE SECLABEL RUN LABEL GOTO IMPORT OPTIONS "
either=" NAME SYMLINK ATTR SYSCTL ENV TAG "
faults=0
fault() { echo "$rules:$1: $2"; faults=$((faults + 1)); }
n=0
while IFS= read -r line || [ -n "$line" ]; do
  n=$((n + 1))
  [[ "$line" =~ ^[[:space:]]*(#|$) ]] && continue
  [[ "$line" == *\\ ]] && { fault "$n" "line continuations are not checked here"; continue; }
  rest=$line
  while [ -n "$rest" ]; do
    if [[ "$rest" =~ ^[[:space:]]*([A-Z_]+)(\{[^}]+\})?[[:space:]]*(==|!=|\+=|-=|:=|=)[[:space:]]*\"([^\"]*)\"[[:space:]]*(,|$)(.*)$ ]]; then
      key=${BASH_REMATCH[1]} op=${BASH_REMATCH[3]} sep=${BASH_REMATCH[5]} rest=${BASH_REMATCH[6]}
      if [[ "$match_only" == *" $key "* ]]; then
        [[ "$op" == "==" || "$op" == "!=" ]] || fault "$n" "$key only matches (== or !=), not '$op'"
      elif [[ "$assign_only" == *" $key "* ]]; then
        [[ "$op" != "==" && "$op" != "!=" ]] || fault "$n" "$key is only assigned, not matched with '$op'"
      elif [[ "$either" != *" $key "* ]]; then
        fault "$n" "unknown key '$key'"
      fi
      if [ "$sep" = "" ] && [[ "$rest" =~ [^[:space:]] ]]; then fault "$n" "text after the last item: '$rest'"; rest=""; fi
      [ "$sep" = "," ] && [[ ! "$rest" =~ [^[:space:]] ]] && fault "$n" "a comma ends the line"
    else
      fault "$n" "not KEY OP \"value\": '${rest#"${rest%%[![:space:]]*}"}'"
      rest=""
    fi
  done
done <"$rules"
for id in "$@"; do
  vid=$(echo "${id%%:*}" | tr 'A-F' 'a-f') pid=$(echo "${id##*:}" | tr 'A-F' 'a-f')
  grep -Eq "ATTRS?\{idVendor\}==\"$vid\".*ATTRS?\{idProduct\}==\"$pid\".*MODE=" "$rules" ||
    fault "-" "no rule gives access to $id"
done
[ "$faults" -eq 0 ]
