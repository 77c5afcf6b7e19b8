#!/usr/bin/env bash
# The Debian packages as a board gets them (cmake/HandscanPackaging.cmake), checked in steps that
# CTest runs in order (fixtures, tests/e2e/package/CMakeLists.txt):
#   build     cpack on the already-built tree (only handscan-package-binaries is brought up to date)
#   contents  dpkg-deb --contents equals the layout in tests/e2e/package/*.contents; control fields
#   unpack    dpkg --root=ROOT --unpack (a throwaway dpkg database; no maintainer script runs)
#   verify    systemd-analyze verify on every installed unit: no output at all, exit 0
#   security  systemd-analyze security --offline of handscan-pipeline.service: exposure <= 2.0
#   maintscripts  dpkg -i, -r, -P with the maintainer scripts in an overlay root (unshare)
# usage: package_test.sh STEP BUILD_DIR SOURCE_DIR
set -euo pipefail
step=$1
build=$(cd "$2" && pwd)
source=$(cd "$3" && pwd)
out=$build/package
root=$out/root

fail() {
    echo "package_test $step: $*" >&2
    exit 1
}
deb_of() {  # the newest .deb of package $1
    ls -t "$out"/"$1"_*.deb 2>/dev/null | head -1
}

case $step in
build)
    cmake --build "$build" --target handscan-package-binaries
    rm -rf "$out" && mkdir -p "$out"
    start=$(date +%s)
    cpack --config "$build/CPackConfig.cmake" -B "$out" >"$out/cpack.log" 2>&1 ||
        { cat "$out/cpack.log"; fail "cpack failed"; }
    for p in handscan handscan-dev-tools; do
        [ -n "$(deb_of $p)" ] || { cat "$out/cpack.log"; fail "no ${p}_*.deb in $out"; }
        echo "$(basename "$(deb_of $p)"): $(du -k "$(deb_of $p)" | cut -f1) KiB"
    done
    echo "cpack: $(($(date +%s) - start)) s"
    ;;
contents)
    for p in handscan handscan-dev-tools; do
        deb=$(deb_of $p)
        [ -n "$deb" ] || fail "no $p package: run the build step first"
        # Paths only (dpkg-deb lists "./usr/bin/x -> target" for links), directories dropped.
        dpkg-deb --contents "$deb" | awk '$1 !~ /^d/ {print $6}' | sed 's|^\./|/|' | LC_ALL=C sort \
            >"$out/$p.contents"
        if ! diff -u "$source/tests/e2e/package/$p.contents" "$out/$p.contents"; then
            fail "$p: the package's files differ from tests/e2e/package/$p.contents (- expected, + packaged)"
        fi
        echo "$p: $(wc -l <"$out/$p.contents") files as laid out"
    done
    control=$(dpkg-deb --field "$(deb_of handscan)" Depends)
    echo "handscan Depends: $control"
    for dep in libc6 libstdc++6 libyaml-cpp0.7 libsystemd0 libgpiod2 libglfw3 adduser systemd cage xwayland; do
        grep -q "\b$dep\b" <<<"$control" || fail "handscan: Depends lacks $dep: $control"
    done
    grep -q "libembree" <<<"$control" && fail "handscan depends on Embree: the simulator leaked into the device package"
    dev=$(dpkg-deb --field "$(deb_of handscan-dev-tools)" Depends)
    grep -q "libembree3" <<<"$dev" || fail "handscan-dev-tools: Depends lacks libembree3: $dev"
    info=$(dpkg-deb --info "$(deb_of handscan)")
    for script in postinst prerm postrm; do
        grep -q " $script " <<<"$info" || fail "handscan: no $script in the control archive"
    done
    conffiles=$(dpkg-deb --ctrl-tarfile "$(deb_of handscan)" | tar -xO ./conffiles)
    grep -qx /etc/handscan/device.yaml <<<"$conffiles" ||
        fail "handscan: /etc/handscan/device.yaml is not a conffile: $conffiles"
    ;;
unpack)
    rm -rf "$root" && mkdir -p "$root/var/lib/dpkg/info" "$root/var/lib/dpkg/updates"
    touch "$root/var/lib/dpkg/status" "$root/var/lib/dpkg/available"
    # --unpack runs no postinst (it would chroot into a root without /bin/sh); --force-depends:
    # the throwaway root has no libc6 etc. in its database, the binaries use the host's.
    dpkg --root="$root" --force-depends --force-not-root --unpack "$(deb_of handscan)" \
        "$(deb_of handscan-dev-tools)" >"$out/dpkg.log" 2>&1 || { cat "$out/dpkg.log"; fail "dpkg --unpack failed"; }
    # What `dpkg --configure` does before the postinst: a first install's conffiles take their
    # names (the postinst itself needs a root that can run programs: see README).
    for new in $(find "$root/etc" -name '*.dpkg-new'); do mv "$new" "${new%.dpkg-new}"; done
    paths=$(dpkg --root="$root" -L handscan)
    grep -qx /usr/bin/handscan-pipeline <<<"$paths" || fail "dpkg -L handscan: $paths"
    [ -f "$root/etc/handscan/device.yaml" ] || fail "no /etc/handscan/device.yaml in $root"
    # The subcommands each tool lists: the device's has neither sim nor eval, handscan-dev both.
    subcommands() { "$1" --help | awk '/^Subcommands:/ {on = 1; next} on && NF {print $1}'; }
    device=$(subcommands "$root/usr/bin/handscan") || fail "the device's handscan does not run"
    dev=$(subcommands "$root/usr/bin/handscan-dev") || fail "handscan-dev does not run"
    grep -qx export <<<"$device" || fail "the device's handscan has no export: $device"
    grep -qxE "sim|eval" <<<"$device" && fail "the device's handscan has sim or eval: $device"
    grep -qx sim <<<"$dev" && grep -qx eval <<<"$dev" || fail "handscan-dev lacks sim or eval: $dev"
    echo "handscan: $(echo $device); handscan-dev: $(echo $dev)"
    echo "unpacked into $root: $(wc -l <<<"$paths") paths of handscan"
    ;;
verify)
    # A root for the verifier: the unpacked packages, the host's own units (sysinit.target and
    # friends) and the host's programs the units run, so every ExecStart= is checked for real.
    vroot=$out/verify-root
    rm -rf "$vroot" && mkdir -p "$vroot/usr/bin" "$vroot/lib/systemd"
    cp -a /lib/systemd/system "$vroot/lib/systemd/"
    cp -a "$root/lib/systemd/system/." "$vroot/lib/systemd/system/"
    cp -a "$root/usr/bin/." "$vroot/usr/bin/"
    for prog in cage mount umount mkdir rm systemctl; do
        p=$(command -v $prog) || fail "$prog is not installed here (tools/install-deps)"
        cp "$p" "$vroot/usr/bin/"
    done
    units=$(cd "$root/lib/systemd/system" && ls)
    [ -n "$units" ] || fail "no units installed"
    for unit in $units; do
        file=$vroot/lib/systemd/system/$unit
        case $unit in *@.service)  # a template: verify an instance of it
            file=$vroot/lib/systemd/system/${unit/@./@sdb1.}
            cp "$vroot/lib/systemd/system/$unit" "$file" ;;
        esac
        log=$(systemd-analyze verify --root="$vroot" "$file" 2>&1) || fail "$unit: $log"
        [ -z "$log" ] || fail "$unit: systemd-analyze verify is not clean: $log"
        echo "verify $unit: clean"
    done
    # systemd-networkd has no verifier: every Section.Key of the .network files must be one that
    # systemd-networkd parses (its configuration tables are strings in the binary).
    networkd=/lib/systemd/systemd-networkd
    [ -x "$networkd" ] || fail "$networkd missing (package systemd)"
    known=$(strings "$networkd" | grep -E '^[A-Z][A-Za-z0-9]*\.[A-Z][A-Za-z0-9]*$' | sort -u)
    for file in "$root"/lib/systemd/network/*.network; do
        section=""
        while IFS= read -r line; do
            case $line in
            \[*\]) section=${line#[}; section=${section%]} ;;
            [A-Za-z]*=*) key=${line%%=*}
                [ "$section" = Match ] && continue
                grep -qx "$section.$key" <<<"$known" || fail "$(basename "$file"): [$section] $key= is not a systemd-networkd setting" ;;
            esac
        done <"$file"
        echo "networkd $(basename "$file"): every key known"
    done
    ;;
security)
    unit=$root/lib/systemd/system/handscan-pipeline.service
    report=$(systemd-analyze security --offline=true --no-pager "$unit" 2>&1) || true
    echo "$report" | grep -v "^✓" | sed '/^$/d'
    level=$(sed -n 's/.*Overall exposure level for handscan-pipeline.service: \([0-9.]*\).*/\1/p' <<<"$report")
    [ -n "$level" ] || fail "no exposure level in: $report"
    awk -v l="$level" 'BEGIN { exit !(l <= 2.0) }' || fail "exposure $level > 2.0"
    echo "handscan-pipeline.service exposure: $level (<= 2.0)"
    ;;
maintscripts)
    # `dpkg -i` with the maintainer scripts for real, in a root that can run them: its /usr an
    # overlay of the host's (programs, libraries) that takes the package's files, its /etc with
    # copies of the host's account files. The postinst makes the users, the storage (tmpfiles)
    # and enables the units there; remove and purge undo what they should.
    command -v unshare >/dev/null || { echo "unshare missing: skipped"; exit 77; }
    croot=$out/chroot
    rm -rf "$croot" "$out/usr-upper" "$out/usr-work"
    mkdir -p "$croot"/{usr,etc,var/lib/dpkg/info,var/lib/dpkg/updates,var/log,run,tmp,dev,proc} \
        "$out/usr-upper" "$out/usr-work"
    for l in bin sbin lib lib64; do ln -s usr/$l "$croot/$l"; done
    for f in passwd group shadow gshadow adduser.conf login.defs nsswitch.conf ld.so.cache \
        ld.so.conf ld.so.conf.d deluser.conf pam.d pam.conf security; do
        [ -e /etc/$f ] && cp -a /etc/$f "$croot/etc/"
    done
    touch "$croot/var/lib/dpkg/status" "$croot/var/lib/dpkg/available"
    deb=$(deb_of handscan)
    unshare --mount --fork bash -euc '
        mount --make-rprivate /
        mount -t overlay overlay -o lowerdir=/usr,upperdir="$2/usr-upper",workdir="$2/usr-work" "$1/usr"
        mount --bind /dev "$1/dev"
        mount --bind /proc "$1/proc"
        dpkg --root="$1" --force-depends -i "$3"
        dpkg --root="$1" -s handscan | grep -qx "Status: install ok installed"
        ls -l "$1/etc/systemd/system/handscan.target.wants" "$1/etc/systemd/system/multi-user.target.wants"
        # remove masks the units (their files are gone, the enablement is kept for a
        # reinstall); purge forgets both, as debhelper-built packages do.
        dpkg --root="$1" --force-depends -r handscan
        test "$(readlink "$1/etc/systemd/system/handscan-pipeline.service")" = /dev/null ||
            { echo "remove did not mask handscan-pipeline.service"; exit 1; }
        dpkg --root="$1" --force-depends -P handscan
        if [ -e "$1/etc/systemd/system/handscan.target.wants/handscan-pipeline.service" ] ||
            [ -L "$1/etc/systemd/system/handscan-pipeline.service" ]; then
            echo "purge left handscan-pipeline.service enabled or masked"; exit 1
        fi
    ' _ "$croot" "$out" "$deb" >"$out/maintscripts.log" 2>&1 ||
        { cat "$out/maintscripts.log"; fail "dpkg -i/-r/-P with the maintainer scripts failed"; }
    grep -v "depends on\|is not installed" "$out/maintscripts.log"
    uid=$(awk -F: '$1 == "handscan" {print $3}' "$croot/etc/passwd")
    [ -n "$uid" ] || fail "postinst made no handscan user"
    grep -q "^handscan-ui:" "$croot/etc/passwd" || fail "postinst made no handscan-ui user"
    grep -Eq "^handscan:[^:]*:[0-9]+:(.*,)?handscan-ui(,|$)" "$croot/etc/group" ||
        fail "handscan-ui is not in group handscan: $(grep ^handscan: "$croot/etc/group")"
    for d in journal calibration; do
        [ "$(stat -c %u "$croot/var/lib/handscan/$d")" = "$uid" ] ||
            fail "/var/lib/handscan/$d is not the handscan user's (tmpfiles)"
    done
    grep -q "handscan-pipeline.service" "$out/maintscripts.log" || fail "the units were not enabled"
    echo "maintainer scripts: users handscan ($uid) and handscan-ui, journal dir, units enabled; remove and purge clean"
    ;;
*)
    fail "unknown step (build, contents, unpack, verify, security, maintscripts)"
    ;;
esac
