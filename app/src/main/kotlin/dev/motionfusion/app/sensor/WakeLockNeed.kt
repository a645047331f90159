package dev.motionfusion.app.sensor

/**
 * Whether a recording must hold a partial wake lock to lose no event with the screen off, decided from
 * the sensors registered (docs/RECORDING.md, "Wake lock"). A non-wake-up sensor's FIFO is not read while
 * the phone sleeps: once full it loses events, so the CPU must stay on. A wake-up sensor wakes the phone
 * itself to deliver its batch before its FIFO overflows (at the latest when the report latency ends), so
 * where every registered sensor is a wake-up one batching at a report latency its FIFO holds, no lock is
 * needed and the phone sleeps between batches.
 */
internal enum class WakeLockNeed(val held: Boolean) {
    /** Every registered sensor is a wake-up one with a FIFO that holds a batch of the report latency: no lock. */
    HARDWARE_BATCHING(false),

    /** A registered sensor has no wake-up variant on this phone: its FIFO would fill unread while the phone sleeps. */
    NOT_WAKE_UP(true),

    /** The FIFOs hold too little for a report latency worth batching (or none): every event would wake the phone. */
    FIFO_TOO_SMALL(true),
    ;

    companion object {
        /** The need for [sensors] (each: a wake-up sensor?, its FIFO's maximum events) registered with [reportLatencyUs]. */
        fun of(sensors: Collection<Pair<Boolean, Int>>, reportLatencyUs: Int): WakeLockNeed = when {
            sensors.isEmpty() || sensors.any { !it.first } -> NOT_WAKE_UP
            reportLatencyUs <= 0 || sensors.any { it.second <= 0 } -> FIFO_TOO_SMALL
            else -> HARDWARE_BATCHING
        }
    }
}
