#!/usr/bin/python3
"""Soak test of cloth_hair_sim_node, run by hand (not in CI): launch/demo.launch headless (the
sheet on the moving mannequin), a grasp taken and released every few seconds by a moving link
(hand_l, else hand_r, else head), for --duration seconds. Every --sample seconds it records the
node's resident memory (VmRSS of /proc/<pid>/status) and the real-time factor of ~status; writes
soak.csv and soak.png (gnuplot) to the output folder and prints the memory growth after the
first minute and whether the node survived. Needs the devel space sourced:
  source build/devel/setup.bash && scripts/soak.py --duration 3600 --out soak_output
It runs its own ROS master on a free port, so it neither needs nor disturbs another one."""
import argparse
import csv
import os
import signal
import socket
import subprocess
import sys
import threading
import time
import xmlrpc.client

NODE = '/cloth_hair_sim'
FRAMES = ['hand_l', 'hand_r', 'head']


def free_port():
    with socket.socket() as s:
        s.bind(('localhost', 0))
        return s.getsockname()[1]


def rss_mib(pid):
    with open('/proc/%d/status' % pid) as f:
        for line in f:
            if line.startswith('VmRSS:'):
                return int(line.split()[1]) / 1024.0
    raise RuntimeError('no VmRSS for pid %d' % pid)


def alive(pid):
    try:
        with open('/proc/%d/status' % pid) as f:
            return 'State:\tZ' not in f.read()
    except OSError:
        return False


def plot(csv_path, png_path):
    script = '''
set terminal pngcairo noenhanced size 1000,560 font ",11"
set output "{png}"
set datafile separator ","
set title "cloth_hair_sim_node soak: demo sheet on the moving mannequin, grasp/release cycles"
set xlabel "elapsed [min]"
set ylabel "resident memory VmRSS [MiB]"
set y2label "real-time factor (median, min over the sample)"
set ytics nomirror
set y2tics
set y2range [0:*]
set key bottom right
set grid
plot "{csv}" every ::1 using ($1/60):2 with linespoints lw 2 title "VmRSS" axes x1y1, \\
     "" every ::1 using ($1/60):3 with linespoints title "RTF median" axes x1y2, \\
     "" every ::1 using ($1/60):4 with lines dt 2 title "RTF min" axes x1y2
'''.format(png=png_path, csv=csv_path)
    subprocess.run(['gnuplot'], input=script.encode(), check=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split('\n')[0])
    ap.add_argument('--duration', type=float, default=3600.0, help='[s] soak length (1 hour)')
    ap.add_argument('--sample', type=float, default=60.0, help='[s] between samples')
    ap.add_argument('--grasp-period', type=float, default=3.0,
                    help='[s] between a grasp and its release (and the next grasp)')
    ap.add_argument('--motion', default='arms_raise', help='mannequin motion (arms_raise, walk)')
    ap.add_argument('--out', default='soak_output', help='folder for soak.csv, soak.png, the log')
    args = ap.parse_args()
    if args.duration <= 0 or args.sample <= 0 or args.grasp_period <= 0:
        sys.exit('soak: --duration, --sample and --grasp-period must be positive')
    os.makedirs(args.out, exist_ok=True)

    def stop(signum, _frame):  # also when started in the background, where SIGINT is ignored
        raise SystemExit('soak: stopped by signal %d' % signum)

    signal.signal(signal.SIGINT, stop)
    signal.signal(signal.SIGTERM, stop)
    port = free_port()
    os.environ['ROS_MASTER_URI'] = 'http://localhost:%d' % port
    # ROS's scripts start with '#!/usr/bin/env python3': a pyenv python first on PATH lacks the
    # ROS modules (the Makefile and demo.sh put /usr/bin first too).
    os.environ['PATH'] = '/usr/bin:' + os.environ.get('PATH', '')
    log = open(os.path.join(args.out, 'soak_launch.log'), 'w')
    launch = subprocess.Popen(['roslaunch', '-p', str(port), 'cloth_hair_sim', 'demo.launch',
                               'headless:=true', 'garment:=sheet', 'motion:=' + args.motion],
                              stdout=log, stderr=subprocess.STDOUT)
    try:
        return soak(args, launch)
    finally:
        if launch.poll() is None:
            launch.send_signal(signal.SIGINT)  # roslaunch shuts its nodes down
            try:
                launch.wait(30)
            except subprocess.TimeoutExpired:
                launch.kill()
        log.close()


def soak(args, launch):
    import rosgraph
    import rospy
    from cloth_hair_sim.msg import SimStatus
    from cloth_hair_sim.srv import GraspGarment, ReleaseGrasp

    deadline = time.time() + 60.0
    while not rosgraph.is_master_online():
        if time.time() > deadline or launch.poll() is not None:
            sys.exit('soak: the launch did not bring up a master; see the log')
        time.sleep(0.5)
    rospy.init_node('soak', anonymous=True, disable_signals=True)
    lock = threading.Lock()
    window = []  # statuses since the last sample
    latest = {}

    def on_status(s):
        with lock:
            window.append(s)
            latest['status'], latest['wall'] = s, time.time()

    rospy.Subscriber(NODE + '/status', SimStatus, on_status)
    rospy.wait_for_service(NODE + '/grasp', timeout=60.0)
    pid = xmlrpc.client.ServerProxy(rosgraph.Master('/soak').lookupNode(NODE)).getPid('/soak')[2]
    grasp = rospy.ServiceProxy(NODE + '/grasp', GraspGarment)
    release = rospy.ServiceProxy(NODE + '/release', ReleaseGrasp)
    while True:  # until the demo's sheet is in
        with lock:
            s = latest.get('status')
        if s is not None and s.garments == 1:
            break
        if time.time() > deadline + 60.0:
            sys.exit('soak: the demo garment never loaded; see the log')
        time.sleep(0.2)
    print('soak: node %s (pid %d), %.0f s, a sample every %.0f s, grasp/release every %.0f s' %
          (NODE, pid, args.duration, args.sample, args.grasp_period))

    csv_path, png_path = os.path.join(args.out, 'soak.csv'), os.path.join(args.out, 'soak.png')
    rows = []
    counts = {'grasps': 0, 'releases': 0, 'grasp_failures': 0}
    held = False
    start = time.time()
    next_sample, next_grasp = start, start + args.grasp_period
    survived = True
    with open(csv_path, 'w', newline='') as f:
        out = csv.writer(f)
        out.writerow(['elapsed_s', 'rss_mib', 'rtf_median', 'rtf_min', 'sim_time_s', 'rollbacks',
                      'grasps', 'releases', 'grasp_failures'])
        while True:
            now = time.time()
            if not alive(pid) or launch.poll() is not None:
                survived = False
                print('soak: the node died after %.0f s' % (now - start))
                break
            if now >= next_grasp:
                next_grasp += args.grasp_period
                try:
                    if held:
                        held = not release(name='soak').success
                        counts['releases'] += 0 if held else 1
                    else:
                        for frame in FRAMES:
                            if grasp(name='soak', garment='sheet', frame_id=frame,
                                     radius=0.3).success:
                                held = True
                                break
                        counts['grasps' if held else 'grasp_failures'] += 1
                except rospy.ServiceException as e:
                    print('soak: service call failed: %s' % e)
            if now >= next_sample:
                with lock:
                    taken = list(window)
                    del window[:]
                    s, fresh = latest['status'], time.time() - latest['wall'] < 2.0
                if not fresh:
                    survived = False
                    print('soak: no ~status for 2 s after %.0f s' % (now - start))
                    break
                rtf = sorted(x.real_time_factor for x in taken if x.state == 'running') or [0.0]
                row = [round(now - start, 1), round(rss_mib(pid), 2), rtf[len(rtf) // 2], rtf[0],
                       round(s.sim_time, 2), s.rollbacks, counts['grasps'], counts['releases'],
                       counts['grasp_failures']]
                out.writerow(row)
                f.flush()
                rows.append(row)
                print('soak: %6.0f s  VmRSS %7.1f MiB  RTF median %.2f min %.2f  sim %.0f s  '
                      'rollbacks %d  grasps %d/%d failed %d' % tuple(row))
                if now - start >= args.duration:
                    break
                next_sample += args.sample
            time.sleep(0.05)
    if len(rows) >= 2:
        plot(csv_path, png_path)
        print('soak: plot %s' % png_path)
    # Growth after the first minute: allocations of the start-up (markers, caches) are over.
    base = next((r for r in rows if r[0] >= 60.0), rows[0]) if rows else None
    if base is not None and rows[-1] is not base:
        hours = (rows[-1][0] - base[0]) / 3600.0
        growth = rows[-1][1] - base[1]
        print('soak: memory %.1f MiB at %.0f s -> %.1f MiB at %.0f s: growth %+.1f MiB '
              '(%+.1f MiB/h)' % (base[1], base[0], rows[-1][1], rows[-1][0], growth,
                                 growth / hours))
    print('soak: the node %s (%d grasps, %d releases, %d grasps found no free vertex)' %
          ('survived' if survived else 'did NOT survive', counts['grasps'], counts['releases'],
           counts['grasp_failures']))
    print('soak: data %s' % csv_path)
    return 0 if survived else 1


if __name__ == '__main__':
    sys.exit(main())
