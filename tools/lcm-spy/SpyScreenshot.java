import java.awt.Component;
import java.awt.Container;
import java.awt.Frame;
import java.awt.Graphics2D;
import java.awt.Point;
import java.awt.Rectangle;
import java.awt.RenderingHints;
import java.awt.Robot;
import java.awt.event.InputEvent;
import java.awt.image.BufferedImage;
import java.io.File;
import javax.imageio.ImageIO;
import javax.swing.JTable;
import javax.swing.SwingUtilities;

/**
 * Screenshot of lcm-spy for the documentation (tools/dev/screenshot_lcm_spy.sh): starts
 * lcm.spy.Spy in this JVM (so it must run with the class path `mvtrack-spy --print-classpath`
 * prints, plus this class), lets it receive for a while, double-clicks one channel to open its
 * message view, places that view right of the channel list, captures both windows with
 * java.awt.Robot and writes them, scaled to a width, as PNG.
 *
 * <p>Usage: java -cp CLASSPATH:DIR SpyScreenshot URL OUT.png WAIT_MS CHANNEL WIDTH
 *
 * <p>Needs a display (Xvfb). Exit status 0 written, 1 failure (no spy window, channel not
 * listed, capture or write failed), 2 usage.
 */
public final class SpyScreenshot {
  private SpyScreenshot() {}

  public static void main(String[] args) throws Exception {
    if (args.length != 5) {
      System.err.println("usage: SpyScreenshot URL OUT.png WAIT_MS CHANNEL WIDTH");
      System.exit(2);
    }
    final String url = args[0];
    final File out = new File(args[1]);
    final long waitMs = Long.parseLong(args[2]);
    final String channel = args[3];
    final int width = Integer.parseInt(args[4]);

    lcm.spy.Spy.main(new String[] {"-l", url});
    Thread.sleep(waitMs);

    Frame spy = null;
    for (Frame f : Frame.getFrames()) {
      if (f.isVisible()) spy = f;
    }
    if (spy == null) fail("no lcm-spy window");
    final Frame spyFrame = spy;
    SwingUtilities.invokeAndWait(() -> spyFrame.setLocation(0, 0));
    final JTable table = findTable(spy);
    if (table == null) fail("no channel table in the lcm-spy window");

    // The channel's row, then a double click on it (lcm-spy opens the message view).
    final int[] row = {-1};
    SwingUtilities.invokeAndWait(() -> {
      for (int r = 0; r < table.getRowCount(); ++r) {
        for (int c = 0; c < table.getColumnCount(); ++c) {
          if (channel.equals(String.valueOf(table.getValueAt(r, c)))) row[0] = r;
        }
      }
    });
    if (row[0] < 0) fail("channel " + channel + " is not listed (did the publishers run?)");
    final Point click = new Point();
    SwingUtilities.invokeAndWait(() -> {
      Rectangle cell = table.getCellRect(row[0], 1, true);
      Point p = new Point(cell.x + cell.width / 2, cell.y + cell.height / 2);
      SwingUtilities.convertPointToScreen(p, table);
      click.setLocation(p);
    });
    Robot robot = new Robot();
    robot.mouseMove(click.x, click.y);
    for (int i = 0; i < 2; ++i) {
      robot.mousePress(InputEvent.BUTTON1_DOWN_MASK);
      robot.mouseRelease(InputEvent.BUTTON1_DOWN_MASK);
      robot.delay(60);
    }
    robot.mouseMove(0, 0);
    Thread.sleep(1500);

    // Place every other visible window (the message view) right of the channel list.
    final Rectangle[] bounds = {null};
    SwingUtilities.invokeAndWait(() -> {
      Rectangle all = spyFrame.getBounds();
      for (Frame f : Frame.getFrames()) {
        if (f == spyFrame || !f.isVisible()) continue;
        f.setLocation(all.x + all.width, 0);
        f.setSize(Math.max(f.getWidth(), 560), Math.max(spyFrame.getHeight(), f.getHeight()));
        all = all.union(f.getBounds());
      }
      bounds[0] = all;
    });
    Thread.sleep(1200);
    BufferedImage shot = robot.createScreenCapture(bounds[0]);

    int height = (int) Math.round(shot.getHeight() * (double) width / shot.getWidth());
    BufferedImage small = new BufferedImage(width, height, BufferedImage.TYPE_INT_RGB);
    Graphics2D g = small.createGraphics();
    g.setRenderingHint(
        RenderingHints.KEY_INTERPOLATION, RenderingHints.VALUE_INTERPOLATION_BICUBIC);
    g.setRenderingHint(RenderingHints.KEY_RENDERING, RenderingHints.VALUE_RENDER_QUALITY);
    g.drawImage(shot, 0, 0, width, height, null);
    g.dispose();
    if (!ImageIO.write(small, "png", out)) fail("no PNG writer");
    System.err.println("SpyScreenshot: wrote " + out + " (" + width + "x" + height + ", captured "
                       + shot.getWidth() + "x" + shot.getHeight() + ")");
    System.exit(0);
  }

  private static JTable findTable(Component c) {
    if (c instanceof JTable) return (JTable) c;
    if (c instanceof Container) {
      for (Component child : ((Container) c).getComponents()) {
        JTable t = findTable(child);
        if (t != null) return t;
      }
    }
    return null;
  }

  private static void fail(String why) {
    System.err.println("SpyScreenshot: " + why);
    System.exit(1);
  }
}
