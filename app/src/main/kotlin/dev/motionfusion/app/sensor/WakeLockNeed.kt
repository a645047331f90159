package dev.motionfusion.app.sensor

import dev.motionfusion.core.event.SessionStream
import dev.motionfusion.core.session.WakeLockUse

/**
 * Whether a recording must hold a partial wake lock to lose no event with the screen off, decided from
 * the sensors registered (docs/RECORDING.md, "Wake lock"). A non-wake-up sensor's FIFO is not read while
 * the phone sleeps: once full it loses events, so the CPU must stay on. A wake-up sensor wakes the phone
 * itself to deliver its batch before its FIFO overflows (at the latest when the report latency ends), so
 * where every registered sensor is a wake-up one batching at a report latency its FIFO holds, no lock is
 * needed and the phone sleeps between batches.
 */
internal enum class WakeLockNeed(val held: Boolean, val key: String) {
    /** Every registered sensor is a wake-up one with a FIFO that holds a batch of the report latency: no lock. */
    HARDWARE_BATCHING(false, "hardware_batching"),

    /** A registered sensor has no wake-up variant on this phone: its FIFO would fill unread while the phone sleeps. */
    NOT_WAKE_UP(true, "not_wake_up"),

    /** The FIFOs hold too little for a report latency worth batching (or none): every event would wake the phone. */
    FIFO_TOO_SMALL(true, "fifo_too_small"),
    ;

    companion object {
        /** The need for [sensors] (each: a wake-up sensor?, its FIFO's maximum events) registered with [reportLatencyUs]. */
        fun of(sensors: Collection<Pair<Boolean, Int>>, reportLatencyUs: Int): WakeLockNeed = when {
            sensors.isEmpty() || sensors.any { !it.first } -> NOT_WAKE_UP
            reportLatencyUs <= 0 || sensors.any { it.second <= 0 } -> FIFO_TOO_SMALL
            else -> HARDWARE_BATCHING
        }

        /**
         * The case for [sensors] (each stream's: a wake-up sensor?, its FIFO's maximum events) registered with
         * [reportLatencyUs], as meta.json's `wake_lock` says it: held or not, why, and the streams that force it
         * (those without a wake-up sensor; those whose FIFO is too small, every one when together they are).
         */
        fun use(sensors: Map<SessionStream, Pair<Boolean, Int>>, reportLatencyUs: Int): WakeLockUse {
            val need = of(sensors.values, reportLatencyUs)
            val forcedBy = when (need) {
                HARDWARE_BATCHING -> emptySet()
                NOT_WAKE_UP -> sensors.filterValues { !it.first }.keys
                FIFO_TOO_SMALL -> sensors.filterValues { it.second <= 0 }.keys.ifEmpty { sensors.keys }
            }
            return WakeLockUse(need.held, need.key, forcedBy.sortedBy { it.ordinal })
        }
    }
}
