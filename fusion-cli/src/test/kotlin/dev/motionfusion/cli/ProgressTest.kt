package dev.motionfusion.cli

import org.junit.jupiter.api.Assertions.assertEquals
import org.junit.jupiter.api.Assertions.assertFalse
import org.junit.jupiter.api.Assertions.assertTrue
import org.junit.jupiter.api.Test
import org.junit.jupiter.api.io.TempDir
import java.io.ByteArrayOutputStream
import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path

/** The progress bar is drawn when standard error is a terminal, whatever standard input and output are, and never otherwise. */
class ProgressTest {
    @TempDir
    lateinit var tmp: Path

    @Test
    fun `standard error is a terminal by the device it is open on`() {
        for (t in listOf("/dev/pts/3", "/dev/tty1", "/dev/tty", "/dev/console")) assertTrue(Terminal.isTerminalDevice(t), t)
        for (t in listOf("pipe:[12345]", "socket:[7]", "/dev/null", "/home/u/log.txt", "/tmp/out")) assertFalse(Terminal.isTerminalDevice(t), t)
        // Through a link as /proc/self/fd/2 shows it.
        val log = Files.createFile(tmp.resolve("log.txt"))
        assertFalse(Terminal.stderrIsTerminal(Files.createSymbolicLink(tmp.resolve("2"), log)))
        // This test's own standard error is captured by the test runner: not a terminal.
        assertFalse(Terminal.stderr)
    }

    @Test
    fun `the bar is drawn only when enabled`() {
        for (enabled in listOf(true, false)) {
            val out = ByteArrayOutputStream()
            val p = Progress(PrintStream(out, true, "UTF-8"), "replay", 10, enabled)
            p.update(5)
            p.finish()
            val text = out.toString("UTF-8")
            if (enabled) assertTrue(text.contains("replay [###############") && text.contains(" 50%"), text) else assertEquals("", text)
        }
    }
}
