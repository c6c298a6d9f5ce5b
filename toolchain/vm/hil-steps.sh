# Sourced by the HIL scenarios inside the VM (hil-vm.sh packs it as /hil/steps.sh).
# BOLO_HIL_SKIP_STEPS: names of steps another VM passed in the same run (scripts/test.sh sets it
# for the x86-64 VMs from the arm64 VM's log); a scenario asks before each step that another
# architecture can stand in for.
hil_skip_step() {  # name -> status 0, and a line saying so, when the step is listed
  case " ${BOLO_HIL_SKIP_STEPS:-} " in
    *" $1 "*) echo "HIL-STEP $1: skipped, passed in another VM of this run (BOLO_HIL_SKIP_STEPS)"; return 0 ;;
  esac
  return 1
}
