/*
 * Test only (tests/fmu/test_platforms.py): ProcessPrng, which Rust's standard library imports
 * from bcryptprimitives.dll (Windows 10 and later have it) and Wine 8 lacks. Built as
 * bcryptprimitives.dll next to the test host, it lets the FMU's DLL load under Wine; it draws
 * from BCryptGenRandom, which Wine has. Nothing of this goes into the FMU.
 */
#include <windows.h>
#include <bcrypt.h>

__declspec(dllexport) BOOL WINAPI ProcessPrng(PBYTE data, SIZE_T size) {
    while (size > 0) {
        ULONG chunk = size > 0x10000000 ? 0x10000000 : (ULONG)size;
        if (BCryptGenRandom(NULL, data, chunk, BCRYPT_USE_SYSTEM_PREFERRED_RNG) != 0) return FALSE;
        data += chunk;
        size -= chunk;
    }
    return TRUE;
}
