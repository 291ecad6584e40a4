// Runs lcm-spy's own window (lcm.spy.Spy, from lcm.jar) in this JVM, with the classpath
// tools/spy gives lcm-spy, and reads its channel table: passes when a channel whose name starts
// with PREFIX is listed with a decoded message (the class lcm-spy found for its fingerprint,
// and the last message decoded with it, no decode errors). Prints every listed channel.
//   java SpyCheck LCM_URL PREFIX SECONDS        (needs a display; exit 0 ok, 1 not seen)
import java.lang.reflect.Field;
import java.util.ArrayList;
import java.util.List;

public class SpyCheck {
  public static void main(String[] args) throws Exception {
    final String url = args[0];
    final String prefix = args[1];
    final long end = System.currentTimeMillis() + (long) (Double.parseDouble(args[2]) * 1000);
    lcm.spy.Spy spy = new lcm.spy.Spy(url);
    Field f = lcm.spy.Spy.class.getDeclaredField("channelList");
    f.setAccessible(true);
    boolean ok = false;
    List<lcm.spy.ChannelData> seen = new ArrayList<>();
    while (!ok && System.currentTimeMillis() < end) {
      Thread.sleep(250);
      seen.clear();
      try {
        synchronized (spy) {
          seen.addAll((ArrayList<lcm.spy.ChannelData>) f.get(spy));
        }
      } catch (java.util.ConcurrentModificationException e) {
        continue;  // the LCM thread added a channel meanwhile: read again
      }
      for (lcm.spy.ChannelData cd : seen) {
        if (cd.name.startsWith(prefix) && cd.cls != null && cd.last != null && cd.nerrors == 0
            && cd.nreceived > 0) {
          ok = true;
        }
      }
    }
    for (lcm.spy.ChannelData cd : seen) {
      System.out.println("lcm-spy lists " + cd.name + ": "
          + (cd.cls == null ? "NOT decoded (no type for its fingerprint)" : "decoded as " + cd.cls.getName())
          + ", " + cd.nreceived + " received, " + cd.nerrors + " decode errors"
          + (cd.last == null ? "" : ", last message object " + cd.last.getClass().getSimpleName()));
    }
    System.out.println(ok ? "SpyCheck: a " + prefix + "* channel is listed and decoded"
                          : "SpyCheck: no " + prefix + "* channel listed and decoded");
    System.exit(ok ? 0 : 1);
  }
}
