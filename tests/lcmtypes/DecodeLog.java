import java.io.ByteArrayInputStream;
import java.io.ByteArrayOutputStream;
import java.io.DataInputStream;
import java.io.DataOutputStream;
import java.io.EOFException;
import java.io.IOException;
import java.lang.reflect.Array;
import java.lang.reflect.Field;
import java.lang.reflect.Modifier;
import java.nio.charset.StandardCharsets;
import java.nio.file.Files;
import java.nio.file.Paths;
import java.util.ArrayList;
import java.util.Arrays;
import java.util.Comparator;
import java.util.List;

import lcm.lcm.LCMEncodable;
import lcm.logging.Log;
import lcm.spy.LCMTypeDatabase;

/**
 * Decodes every event of an LCM log with the LCM types that lcm-spy finds on the class path
 * (lcm.spy.LCMTypeDatabase, looked up by fingerprint, exactly as lcm-spy does), checks that each
 * decoded message re-encodes to the same bytes, and prints the canonical dump described in
 * tests/lcmtypes/sample_messages.h (fields via reflection, sorted by name).
 *
 * <p>Usage: java -cp LCM_JAR:TYPES_JAR:DIR DecodeLog [--expected DUMP_FILE] LOG
 *
 * <p>With --expected the output must equal DUMP_FILE (the C++ side's dump); the first
 * difference is reported. Exit status: 0 on success, 1 on a decode, re-encode or comparison
 * failure, 2 on bad usage.
 */
public final class DecodeLog {
  private DecodeLog() {}

  public static void main(String[] args) throws Exception {
    String expectedPath = null;
    String logPath = null;
    for (int i = 0; i < args.length; ++i) {
      if (args[i].equals("--expected") && i + 1 < args.length) {
        expectedPath = args[++i];
      } else if (logPath == null && !args[i].startsWith("--")) {
        logPath = args[i];
      } else {
        System.err.println("usage: DecodeLog [--expected DUMP_FILE] LOG");
        System.exit(2);
      }
    }
    if (logPath == null) {
      System.err.println("usage: DecodeLog [--expected DUMP_FILE] LOG");
      System.exit(2);
    }

    LCMTypeDatabase types = new LCMTypeDatabase();
    Log log = new Log(logPath, "r");
    StringBuilder out = new StringBuilder();
    boolean ok = true;
    int index = 0;
    while (true) {
      Log.Event event;
      try {
        event = log.readNext();
      } catch (EOFException end) {
        break;
      }
      if (event == null) break;
      String where = "event " + index + " on channel " + event.channel;
      if (event.data.length < 8) {
        System.err.println(where + ": shorter than a fingerprint");
        ok = false;
        ++index;
        continue;
      }
      long fingerprint = new DataInputStream(new ByteArrayInputStream(event.data)).readLong();
      Class<?> cls = types.getClassByFingerprint(fingerprint);
      if (cls == null) {
        System.err.printf("%s: no type on the class path has fingerprint 0x%016x%n",
                          where, fingerprint);
        ok = false;
        ++index;
        continue;
      }
      Object msg = cls.getConstructor(byte[].class).newInstance((Object) event.data);
      ByteArrayOutputStream reencoded = new ByteArrayOutputStream();
      ((LCMEncodable) msg).encode(new DataOutputStream(reencoded));
      if (!Arrays.equals(reencoded.toByteArray(), event.data)) {
        System.err.println(where + ": " + cls.getName() + " re-encodes to different bytes");
        ok = false;
      }
      out.append("event ").append(index).append(" channel=").append(event.channel)
          .append(" type=").append(cls.getSimpleName()).append('\n');
      dump(msg, "", out);
      ++index;
    }
    log.close();
    System.out.print(out);

    if (expectedPath != null) {
      String expected =
          new String(Files.readAllBytes(Paths.get(expectedPath)), StandardCharsets.UTF_8);
      if (!expected.equals(out.toString())) {
        reportFirstDifference(expected, out.toString());
        ok = false;
      } else {
        System.err.println("DecodeLog: " + index + " events match " + expectedPath);
      }
    }
    System.exit(ok ? 0 : 1);
  }

  private static void reportFirstDifference(String expected, String actual) {
    String[] want = expected.split("\n", -1);
    String[] got = actual.split("\n", -1);
    int n = Math.min(want.length, got.length);
    for (int i = 0; i < n; ++i) {
      if (!want[i].equals(got[i])) {
        System.err.println("DecodeLog: output differs from the C++ dump at line " + (i + 1));
        System.err.println("  C++:  " + want[i]);
        System.err.println("  Java: " + got[i]);
        return;
      }
    }
    System.err.println("DecodeLog: output has " + got.length + " lines, the C++ dump "
                       + want.length);
  }

  /** Appends the canonical dump of an LCM message object (public instance fields). */
  private static void dump(Object msg, String prefix, StringBuilder out) throws Exception {
    List<Field> fields = new ArrayList<>();
    for (Field f : msg.getClass().getFields()) {
      if (!Modifier.isStatic(f.getModifiers())) fields.add(f);
    }
    fields.sort(Comparator.comparing(Field::getName));
    for (Field f : fields) {
      Object value = f.get(msg);
      if (value != null && value.getClass().isArray()) {
        for (int i = 0; i < Array.getLength(value); ++i) {
          dumpValue(Array.get(value, i), prefix + f.getName() + "[" + i + "]", out);
        }
      } else {
        dumpValue(value, prefix + f.getName(), out);
      }
    }
  }

  private static void dumpValue(Object value, String path, StringBuilder out) throws Exception {
    if (value instanceof LCMEncodable) {
      dump(value, path + ".", out);
      return;
    }
    out.append(path).append('=');
    if (value instanceof Float) {
      out.append(realText(((Float) value).doubleValue()));
    } else if (value instanceof Double) {
      out.append(realText((Double) value));
    } else if (value instanceof Boolean) {
      out.append(((Boolean) value) ? "true" : "false");
    } else if (value instanceof String) {
      out.append(stringText((String) value));
    } else if (value instanceof Byte || value instanceof Short || value instanceof Integer
               || value instanceof Long) {
      out.append(((Number) value).longValue());
    } else {
      throw new IOException("unsupported field type at " + path + ": " + value);
    }
    out.append('\n');
  }

  private static String realText(double v) {
    return String.format("0x%016x", Double.doubleToRawLongBits(v));
  }

  private static String stringText(String s) {
    StringBuilder b = new StringBuilder("\"");
    for (byte raw : s.getBytes(StandardCharsets.UTF_8)) {
      int c = raw & 0xff;
      if (c < 0x20 || c > 0x7e || c == '"' || c == '\\') {
        b.append(String.format("\\x%02x", c));
      } else {
        b.append((char) c);
      }
    }
    return b.append('"').toString();
  }
}
