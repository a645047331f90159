package dev.motionfusion.cli

import java.io.PrintStream

/**
 * A progress bar on stderr, drawn only when the process runs on a terminal (System.console()
 * is not null), at most 10 times a second; silent when piped or redirected.
 */
internal class Progress(private val err: PrintStream, private val label: String, private val total: Long?) {
    private val enabled = System.console() != null
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
