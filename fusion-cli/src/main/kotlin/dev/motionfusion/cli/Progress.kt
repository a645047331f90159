package dev.motionfusion.cli

import java.io.PrintStream
import java.nio.file.Files
import java.nio.file.Path

/**
 * A progress bar on stderr, drawn only when standard error is a terminal ([Terminal.stderr]), at most
 * 10 times a second; silent when standard error is piped or redirected, even with standard input and
 * output on a terminal.
 */
internal class Progress(private val err: PrintStream, private val label: String, private val total: Long?, private val enabled: Boolean = Terminal.stderr) {
    private var lastDraw = 0L
    private var drawn = false

    fun update(done: Long) {
        if (!enabled) return
        val now = System.nanoTime()
        if (now - lastDraw < 100_000_000L) return
        lastDraw = now
        drawn = true
        val text = if (total != null && total > 0) {
            val f = (done.toDouble() / total).coerceIn(0.0, 1.0)
            val width = 30
            val filled = (f * width).toInt()
            "\r$label [" + "#".repeat(filled) + " ".repeat(width - filled) + "] %3d%%".format((f * 100).toInt())
        } else {
            "\r$label %,d events".format(done)
        }
        err.print(text)
        err.flush()
    }

    fun finish() {
        if (drawn) {
            err.print("\r" + " ".repeat(label.length + 48) + "\r")
            err.flush()
        }
    }
}

/** Whether standard error is a terminal, decided once per process. */
internal object Terminal {
    val stderr: Boolean by lazy { stderrIsTerminal(Path.of("/proc/self/fd/2")) }

    /**
     * Where the system shows what a descriptor is open on ([fd], Linux's /proc/self/fd/2), whether that is a
     * terminal device; elsewhere the console check (System.console(), which looks at standard input and output,
     * with Console.isTerminal where the JDK has it, 22 and newer).
     */
    fun stderrIsTerminal(fd: Path): Boolean {
        val target = runCatching { Files.readSymbolicLink(fd).toString() }.getOrNull() ?: return consoleIsTerminal()
        return isTerminalDevice(target)
    }

    /** /dev/pts/N, /dev/ttyN, /dev/tty, /dev/console: terminals; files, pipes (pipe:[…]), sockets, /dev/null: not. */
    fun isTerminalDevice(target: String): Boolean =
        target.startsWith("/dev/pts/") || target.startsWith("/dev/tty") || target == "/dev/console"

    private fun consoleIsTerminal(): Boolean {
        val console = System.console() ?: return false
        val isTerminal = runCatching { console.javaClass.getMethod("isTerminal") }.getOrNull() ?: return true
        return runCatching { isTerminal.invoke(console) as Boolean }.getOrDefault(false)
    }
}
